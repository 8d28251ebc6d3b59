# src/study.mk: fragment owned by one module
