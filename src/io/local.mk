# src/io/: file writers (VTK/PVD shapes, atomic text output, FOLD).
src_libsmoothfold_a_SOURCES += src/io/vtk.c src/io/vtk.h \
	src/io/outbuf.c src/io/outbuf.h src/io/outdir.c src/io/outdir.h \
	src/io/fold_write.c src/io/fold_frames.c src/io/fold.h
