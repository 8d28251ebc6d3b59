# src/pattern/: the study in memory (pattern.h), its reader (study.c) and
# the crease-pattern topology (faces, vertex cycles, face tree).
src_libsmoothfold_a_SOURCES += src/pattern/pattern.h \
	src/pattern/study.c src/pattern/study.h \
	src/pattern/topology.c src/pattern/topology.h
