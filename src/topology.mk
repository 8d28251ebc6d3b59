# src/topology.mk: fragment owned by one module
