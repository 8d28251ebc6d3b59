# src/analysis/: what is computed from the model, one folder per concern
# (README.md): each folder keeps its own fragment.
include src/analysis/linalg/local.mk
include src/analysis/equilibrium/local.mk
include src/analysis/start/local.mk
include src/analysis/stability/local.mk
include src/analysis/bifurcation/local.mk
include src/analysis/dynamics/local.mk
include src/analysis/compare/local.mk
include src/analysis/sweep/local.mk
include src/analysis/validity/local.mk
