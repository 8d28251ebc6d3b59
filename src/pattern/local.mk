# src/pattern/: the study in memory (pattern.h), its reader (study.c) and
# the crease-pattern topology (faces, vertex cycles, face tree); crease
# patterns as FOLD sees them (cpattern.h), the tessellation generators and
# the FOLD reader.
src_libsmoothfold_a_SOURCES += src/pattern/pattern.h \
	src/pattern/study.c src/pattern/study.h src/pattern/assignment.c \
	src/pattern/topology.c src/pattern/topology.h \
	src/pattern/cpattern.c src/pattern/cpattern.h src/pattern/cp_study.c \
	src/pattern/generators.c src/pattern/generators.h
