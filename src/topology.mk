# src/topology.mk: fragment owned by one module
# faces, fold sides, vertex cycles, face tree and face bodies
src_libsmoothfold_a_SOURCES += src/topology.c
