# continuation/: generic path-following engine (owner: continuation work)
noinst_LIBRARIES += continuation/libcont.a
continuation_libcont_a_SOURCES = continuation/cont.c continuation/cont.h \
	continuation/cont_impl.h \
	continuation/cont_bordered.c continuation/cont_corrector.c \
	continuation/cont_special.c continuation/cont_step.c continuation/cont_switch.c \
	continuation/cont_lapack.c continuation/cont_lapack.h \
	continuation/cont_mumps.c continuation/cont_mumps.h continuation/cont_blockelim.c
