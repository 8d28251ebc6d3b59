# src/model/: fold sections, kinematics (folding maps, loop constraints),
# energy terms, and the scene that binds study, topology and model.
src_libsmoothfold_a_SOURCES += src/model/shape.c src/model/shape.h \
	src/model/affine.c src/model/affine.h \
	src/model/kinematics.c src/model/kinematics.h \
	src/model/energy.c src/model/energy.h \
	src/model/poses.c src/model/poses.h \
	src/model/scene.c src/model/scene.h
