# tests/cont.mk: fragment owned by one module
