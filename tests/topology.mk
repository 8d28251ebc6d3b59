# tests/topology.mk: fragment owned by one module
