# tests/docs.mk: what a user reads: the guides' commands run as written and
# the links of README.md and docs/ resolve (test_docs.sh), the man page
# renders (test_man.sh), the bash completion offers commands and keys
# (test_completion.sh).
TESTS += tests/test_docs.sh tests/test_man.sh tests/test_completion.sh
EXTRA_DIST += tests/test_docs.sh tests/test_man.sh tests/test_completion.sh
# the documents test_docs.sh reads (README.md is distributed by automake)
EXTRA_DIST += docs
