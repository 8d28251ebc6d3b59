# tests/accuracy.mk: reference comparison (compare.c) through the program,
# convergence in K, and regression against stored results
TESTS += tests/test_compare.sh tests/test_accuracy.sh tests/test_regress.sh
EXTRA_DIST += tests/test_compare.sh tests/test_accuracy.sh tests/test_regress.sh \
	tests/fold1_arc.awk studies/fold1-buckle.cfg studies/snap1.cfg studies/square4-inplane.cfg \
	studies/hard-near-pi.cfg studies/hard-stiff-ratio.cfg studies/hard-tiny-width.cfg \
	tests/compare/badkind.csv tests/compare/colsline.csv tests/compare/good.csv \
	tests/compare/longrow.csv tests/compare/nan.csv tests/compare/nokind.csv \
	tests/compare/noprov.csv tests/compare/norows.csv tests/compare/shortrow.csv \
	tests/compare/text.csv \
	tests/regress/sample.sh tests/regress/regenerate.sh \
	tests/regress/strip3.csv tests/regress/fold1.csv tests/regress/waterbomb2.csv \
	tests/regress/square4.csv tests/regress/square4-stiff.csv \
	tests/regress/square4-narrow.csv tests/regress/square4-corner.csv \
	tests/regress/square4-irregular.csv tests/regress/fold1-buckle.csv \
	tests/regress/snap1.csv tests/regress/square4-inplane.csv tests/regress/hard-near-pi.csv \
	tests/regress/hard-stiff-ratio.csv tests/regress/hard-tiny-width.csv
