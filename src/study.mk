# src/study.mk: the study file (schema, reader, --set, writer, accessors)
src_libsmoothfold_a_SOURCES += src/study.c src/study.h
