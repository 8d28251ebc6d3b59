# continuation/: generic path-following engine (owner: continuation work)
noinst_LIBRARIES += continuation/libcont.a
continuation_libcont_a_SOURCES = continuation/cont.c continuation/cont.h continuation/cont_lapack.c continuation/cont_lapack.h
