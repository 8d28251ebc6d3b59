# tests/study.mk: the study reader (src/pattern/study*.c)
check_PROGRAMS += tests/test_study tests/test_study_set
TESTS += tests/test_study tests/test_study_set
tests_test_study_SOURCES = tests/test_study.c tests/study_test.h
tests_test_study_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_study_LDADD = $(SF_TEST_LIBS)
tests_test_study_set_SOURCES = tests/test_study_set.c tests/study_test.h
tests_test_study_set_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_study_set_LDADD = $(SF_TEST_LIBS)
# studies, broken studies and the manual read by the test (from SF_SRCDIR)
EXTRA_DIST += docs/reference/study-keys.md \
	studies/fold1.cfg \
	studies/square4-corner.cfg \
	studies/square4-irregular.cfg \
	studies/square4-narrow.cfg \
	studies/square4-stiff.cfg \
	studies/square4.cfg \
	studies/strip3.cfg \
	studies/waterbomb2.cfg \
	tests/bad/study_analysis_type.cfg \
	tests/bad/study_analysis_type.expect \
	tests/bad/study_constraints.cfg \
	tests/bad/study_constraints.expect \
	tests/bad/study_continuity.cfg \
	tests/bad/study_continuity.expect \
	tests/bad/study_dup_fold_name.cfg \
	tests/bad/study_dup_fold_name.expect \
	tests/bad/study_dup_probe.cfg \
	tests/bad/study_dup_probe.expect \
	tests/bad/study_dup_vertex.cfg \
	tests/bad/study_dup_vertex.expect \
	tests/bad/study_float_for_int.cfg \
	tests/bad/study_float_for_int.expect \
	tests/bad/study_fold_material_no_E.cfg \
	tests/bad/study_fold_material_no_E.expect \
	tests/bad/study_gravity_no_density.cfg \
	tests/bad/study_gravity_no_density.expect \
	tests/bad/study_gravity_no_faces.cfg \
	tests/bad/study_gravity_no_faces.expect \
	tests/bad/study_inf.cfg \
	tests/bad/study_inf.expect \
	tests/bad/study_int_overflow.cfg \
	tests/bad/study_int_overflow.expect \
	tests/bad/study_missing_fixed.cfg \
	tests/bad/study_missing_fixed.expect \
	tests/bad/study_missing_name.cfg \
	tests/bad/study_missing_name.expect \
	tests/bad/study_missing_to.cfg \
	tests/bad/study_missing_to.expect \
	tests/bad/study_mixed_array.cfg \
	tests/bad/study_mixed_array.expect \
	tests/bad/study_modes.cfg \
	tests/bad/study_modes.expect \
	tests/bad/study_modes_neg.cfg \
	tests/bad/study_modes_neg.expect \
	tests/bad/study_neg_E.cfg \
	tests/bad/study_neg_E.expect \
	tests/bad/study_neg_density.cfg \
	tests/bad/study_neg_density.expect \
	tests/bad/study_neg_inf.cfg \
	tests/bad/study_neg_inf.expect \
	tests/bad/study_neg_setback.cfg \
	tests/bad/study_neg_setback.expect \
	tests/bad/study_neg_width.cfg \
	tests/bad/study_neg_width.expect \
	tests/bad/study_no_width.cfg \
	tests/bad/study_no_width.expect \
	tests/bad/study_nu.cfg \
	tests/bad/study_nu.expect \
	tests/bad/study_nu_low.cfg \
	tests/bad/study_nu_low.expect \
	tests/bad/study_outline_twice.cfg \
	tests/bad/study_outline_twice.expect \
	tests/bad/study_outline_vertex.cfg \
	tests/bad/study_outline_vertex.expect \
	tests/bad/study_report_probe.cfg \
	tests/bad/study_report_probe.expect \
	tests/bad/study_same_ends.cfg \
	tests/bad/study_same_ends.expect \
	tests/bad/study_stage_gap.cfg \
	tests/bad/study_stage_gap.expect \
	tests/bad/study_syntax.cfg \
	tests/bad/study_syntax.expect \
	tests/bad/study_syntax_brace.cfg \
	tests/bad/study_syntax_brace.expect \
	tests/bad/study_unknown_face_material.cfg \
	tests/bad/study_unknown_face_material.expect \
	tests/bad/study_unknown_group.cfg \
	tests/bad/study_unknown_group.expect \
	tests/bad/study_unknown_key.cfg \
	tests/bad/study_unknown_key.expect \
	tests/bad/study_unknown_key_fold.cfg \
	tests/bad/study_unknown_key_fold.expect \
	tests/bad/study_unknown_key_top.cfg \
	tests/bad/study_unknown_key_top.expect \
	tests/bad/study_unknown_material.cfg \
	tests/bad/study_unknown_material.expect \
	tests/bad/study_unknown_vertex.cfg \
	tests/bad/study_unknown_vertex.expect \
	tests/bad/study_vec_len.cfg \
	tests/bad/study_vec_len.expect \
	tests/bad/study_wrong_type.cfg \
	tests/bad/study_wrong_type.expect \
	tests/bad/study_zero_stage.cfg \
	tests/bad/study_zero_stage.expect \
	tests/bad/study_zero_thickness.cfg \
	tests/bad/study_zero_thickness.expect \
	tests/bad/study_zero_width.cfg \
	tests/bad/study_zero_width.expect
