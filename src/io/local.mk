# src/io/: file writers (VTK/PVD shapes, atomic text output).
src_libsmoothfold_a_SOURCES += src/io/vtk.c src/io/vtk.h \
	src/io/outbuf.c src/io/outbuf.h src/io/outdir.c src/io/outdir.h
