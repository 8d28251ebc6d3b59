/* study.c - the study file (study.h, docs/reference/study-keys.md): the schema,
 * sf_study_load / sf_study_free, lookups by name.  The other parts of the
 * reader are listed in study_impl.h.
 *
 * Everything a study may contain is listed in ONE table, `schema` below:
 * path pattern, type, bounds, default, unit and a line of documentation.
 * The generic checker (study_check.c) walks the libconfig tree against it
 * (unknown keys, types, finiteness, bounds, required keys, choices); the
 * semantic pass (study_fill.c) then resolves names and fills the sf_study
 * of pattern.h.  To add a key for a new module, add a row (and document it
 * in docs/reference/study-keys.md; the test checks that every row is mentioned
 * there).
 *
 * Path patterns: "a.b" a member of group a; "a.*" any member of a group of
 * free names (vertices, materials); "a[]" each element of list a.
 */
#include "study_impl.h"
#include "facets.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define G SF_KEY_GROUP
#define NAMED SF_KEY_NAMED
#define LIST SF_KEY_LIST
#define NUM SF_KEY_NUMBER
#define INT SF_KEY_INT
#define STR SF_KEY_STRING
#define BOOL SF_KEY_BOOL
#define V2 SF_KEY_VEC2
#define V3 SF_KEY_VEC3
#define B3 SF_KEY_BOOL3
#define NAMES SF_KEY_NAMES
#define REQ SF_KEY_REQUIRED
#define POS SF_KEY_GT            /* with lo = 0 */
#define NONNEG SF_KEY_GE         /* with lo = 0 */
#define IDENT SF_KEY_IDENT
#define AUTO SF_KEY_AUTO
#define DYN SF_KEY_DYNAMICS
#define RANGE (SF_KEY_GE | SF_KEY_LE)

static const sf_study_key schema[] = {
    /* path                        type   flags           lo    hi    default        choices  unit  doc */
    {"name",                       STR,   REQ | SF_KEY_FILESAFE, 0, 0, NULL, NULL, "-", "study name, used in output file names ([A-Za-z0-9_.-])"},
    {"description",                STR,   0,              0, 0,       NULL,          NULL, "-", "free text"},

    {"vertices",                   NAMED, REQ,            0, 0,       NULL,          NULL, "-", "named points of the crease pattern, in study order"},
    {"vertices.*",                 V2,    0,              0, 0,       NULL,          NULL, "m", "reference position [x, y] of the vertex"},

    {"sheet",                      G,     REQ,            0, 0,       NULL,          NULL, "-", "the sheet"},
    {"sheet.outline",              NAMES, REQ,            0, 0,       NULL,          NULL, "-", "outline polygon: names of its corner vertices, in order"},

    {"materials",                  NAMED, REQ,            0, 0,       NULL,          NULL, "-", "named materials"},
    {"materials.*",                G,     0,              0, 0,       NULL,          NULL, "-", "one material"},
    {"materials.*.E",              NUM,   POS,            0, 0,       NULL,          NULL, "Pa", "Young's modulus (required for materials used by folds)"},
    {"materials.*.nu",             NUM,   SF_KEY_GT | SF_KEY_LT, -1, 0.5, NULL,      NULL, "-", "Poisson ratio in (-1, 0.5) (required for materials used by folds)"},
    {"materials.*.thickness",      NUM,   REQ | POS,      0, 0,       NULL,          NULL, "m", "thickness"},
    {"materials.*.density",        NUM,   NONNEG,         0, 0,       NULL,          NULL, "kg/m^3", "density (required for materials in use when gravity or inertia is on)"},

    {"faces",                      G,     0,              0, 0,       NULL,          NULL, "-", "the rigid faces"},
    {"faces.material",             STR,   REQ,            0, 0,       NULL,          NULL, "-", "material of the faces (thickness, density; needed for gravity; E and nu when they bend)"},
    {"faces.bending",              BOOL,  0,              0, 0,       "false",       NULL, "-", "faces bend: each face is split into rigid triangles joined by facet hinges whose stiffness follows from the face material (docs/guides/bending-faces.md)"},
    {"faces.bending_coefficient",  NUM,   POS,            0, 0,       "0.55",        NULL, "-", "C_B of the facet hinge stiffness C_B (L/t)^(1/3) E t^3 / (12 (1 - nu^2)) (Filipov et al. 2017; docs/guides/bending-faces.md)"},
    {"faces.facet_width",          NUM,   SF_KEY_GT | SF_KEY_LE, 0, 0.25, "0.02", NULL, "-", "band width of a facet hinge as a fraction of the shortest side of its face"},
    {"faces.facets",               NAMES, 0,              0, 0,       NULL,          NULL, "-", "facet edges given, each \"from to\" (two vertex names); faces without one are triangulated automatically (FOLD's F edges, written by import)"},

    {"defaults",                   G,     AUTO,           0, 0,       NULL,          NULL, "-", "fold settings used where a fold does not give its own"},
    {"defaults.width",             NUM,   POS,            0, 0,       NULL,          NULL, "m", "band width w"},
    {"defaults.setback",           V2,    NONNEG,         0, 0,       "[0.0, 0.0]",  NULL, "m", "setbacks [at from, at to]"},
    {"defaults.continuity",        INT,   RANGE,          1, 2,       "1",           NULL, "-", "1 (G1) or 2 (G2)"},
    {"defaults.modes",             INT,   RANGE,          0, SF_STUDY_MAX_MODES, "0", NULL, "-", "K, extra curvature modes per fold (0 = circular arc)"},
    {"defaults.material",          STR,   0,              0, 0,       "fold",        NULL, "-", "fold material"},
    {"defaults.rest_angle",        NUM,   0,              0, 0,       "0.0",         NULL, "rad", "stress-free fold angle"},

    {"folds",                      LIST,  REQ,            0, 0,       NULL,          NULL, "-", "the folds, in study order"},
    {"folds[]",                    G,     0,              0, 0,       NULL,          NULL, "-", "one fold"},
    {"folds[].name",               STR,   IDENT,          0, 0,       NULL,          NULL, "-", "optional name (for --set folds[name].key and messages)"},
    {"folds[].from",               STR,   REQ,            0, 0,       NULL,          NULL, "-", "start vertex a"},
    {"folds[].to",                 STR,   REQ,            0, 0,       NULL,          NULL, "-", "end vertex b"},
    {"folds[].width",              NUM,   POS,            0, 0,       NULL,          NULL, "m", "band width (else defaults.width)"},
    {"folds[].setback",            V2,    NONNEG,         0, 0,       NULL,          NULL, "m", "setbacks [at from, at to] (else defaults.setback)"},
    {"folds[].continuity",         INT,   RANGE,          1, 2,       NULL,          NULL, "-", "1 or 2 (else defaults.continuity)"},
    {"folds[].modes",              INT,   RANGE,          0, SF_STUDY_MAX_MODES, NULL, NULL, "-", "K (else defaults.modes)"},
    {"folds[].material",           STR,   0,              0, 0,       NULL,          NULL, "-", "material (else defaults.material)"},
    {"folds[].group",              STR,   0,              0, 0,       NULL,          NULL, "-", "actuation group the fold belongs to"},
    {"folds[].rest_angle",         NUM,   0,              0, 0,       NULL,          NULL, "rad", "stress-free fold angle (else defaults.rest_angle)"},
    {"folds[].assignment",         STR,   0,              0, 0,       NULL,          "M|V",   "-", "mountain or valley (valley positive): check rejects a rest angle of the other sign"},
    {"folds[].damping",            NUM,   POS,            0, 0,       NULL,          NULL, "J s", "dynamics: damping coefficient of the fold angle (else analysis.damping)"},

    {"fixed_face",                 V2,    REQ,            0, 0,       NULL,          NULL, "m", "a point inside the fixed face"},

    {"loads",                      LIST,  0,              0, 0,       NULL,          NULL, "-", "dead point loads"},
    {"loads[]",                    G,     0,              0, 0,       NULL,          NULL, "-", "one point load"},
    {"loads[].at",                 V2,    REQ,            0, 0,       NULL,          NULL, "m", "material point (reference coordinates)"},
    {"loads[].force",              V3,    REQ,            0, 0,       NULL,          NULL, "N", "force at full load"},
    {"loads[].stage",              INT,   SF_KEY_GE,      1, 0,       "1",           NULL, "-", "load stage (1, 2, ...)"},

    {"gravity",                    G,     0,              0, 0,       NULL,          NULL, "-", "gravity on faces and folds (absent: none)"},
    {"gravity.g",                  V3,    REQ,            0, 0,       NULL,          NULL, "m/s^2", "acceleration of gravity"},
    {"gravity.stage",              INT,   SF_KEY_GE,      1, 0,       "1",           NULL, "-", "load stage"},
    {"gravity.enabled",            BOOL,  0,              0, 0,       "true",        NULL, "-", "false switches gravity off"},

    {"actuation",                  LIST,  0,              0, 0,       NULL,          NULL, "-", "actuation groups"},
    {"actuation[]",                G,     0,              0, 0,       NULL,          NULL, "-", "one group"},
    {"actuation[].name",           STR,   REQ | IDENT,    0, 0,       NULL,          NULL, "-", "group name (folds join with group = name)"},
    {"actuation[].rest_angle",     NUM,   REQ,            0, 0,       NULL,          NULL, "rad", "rest angle of its folds at actuation parameter 1"},
    {"actuation[].schedule",       LIST,  0,              0, 0,       NULL,          NULL, "-", "dynamics: actuation factor of this group over time, piecewise linear (overrides p for the group)"},
    {"actuation[].schedule[]",     G,     0,              0, 0,       NULL,          NULL, "-", "one point of the group's schedule"},
    {"actuation[].schedule[].t",   NUM,   REQ | NONNEG,   0, 0,       NULL,          NULL, "s", "time"},
    {"actuation[].schedule[].value", NUM, REQ,            0, 0,       NULL,          NULL, "-", "actuation factor at t (rest angle = value * rest_angle)"},

    {"supports",                   LIST,  0,              0, 0,       NULL,          NULL, "-", "point supports / prescribed displacements"},
    {"supports[]",                 G,     0,              0, 0,       NULL,          NULL, "-", "one support"},
    {"supports[].at",              V2,    REQ,            0, 0,       NULL,          NULL, "m", "material point"},
    {"supports[].fix",             B3,    0,              0, 0,       "[true, true, true]", NULL, "-", "which displacement components are prescribed"},
    {"supports[].value",           V3,    0,              0, 0,       "[0.0, 0.0, 0.0]", NULL, "m", "prescribed displacement at full factor"},

    {"probes",                     LIST,  0,              0, 0,       NULL,          NULL, "-", "points whose displacement is reported"},
    {"probes[]",                   G,     0,              0, 0,       NULL,          NULL, "-", "one probe"},
    {"probes[].name",              STR,   REQ | IDENT,    0, 0,       NULL,          NULL, "-", "probe name"},
    {"probes[].at",                V2,    REQ,            0, 0,       NULL,          NULL, "m", "material point"},

    {"solver",                     G,     AUTO,           0, 0,       NULL,          NULL, "-", "model and solver settings"},
    {"solver.constraints",         STR,   0,              0, 0,       "exact",       "exact|penalty", "-", "vertex loop closure: exact (multipliers) or penalty (the paper's code)"},
    {"solver.penalty_rotation",    NUM,   POS,            0, 0,       "100.0",       NULL, "J", "lambda_R, penalty on the rotation entries"},
    {"solver.penalty_translation", NUM,   POS,            0, 0,       "1.0",         NULL, "J/m^2", "lambda_d, penalty on the translation"},
    {"solver.quadrature",          INT,   RANGE, SF_QUADRATURE_MIN, SF_QUADRATURE_MAX, "24",          NULL, "-", "Gauss-Legendre points across a fold"},
    {"solver.tolerance",           NUM,   POS,            0, 0,       "1e-10",       NULL, "-", "Newton tolerance (scaled residual norm)"},
    {"solver.formulation",         STR,   0,              0, 0,       "auto",        "auto|folds|poses", "-", "unknowns: fold coordinates (loops closed by 6 rows per interior vertex) or face poses (6 rows per fold, sparse; exact constraints only), docs/design/model.md; auto: poses above solver.auto_unknowns, else folds"},
    {"solver.auto_unknowns",       INT,   SF_KEY_GE,      0, 0,       "300",         NULL, "-", "equilibrium paths: the size above which solver.formulation, analysis.flat_start and analysis.step_norm, all three \"auto\", choose \"poses\", \"sparse\", \"rms\" (unknowns in fold coordinates: angles, modes, loop and support multipliers; a sheet with loops, exact closure, no branch_depth); otherwise \"folds\", \"multipliers\" below it and \"limit\" above it or with analysis.branch_depth >= 1, \"sum\"; docs/reference/study-keys.md \"Large sheets\""},
    {"solver.pose_rows",           STR,   0,              0, 0,       "all",         "all|independent", "-", "face poses: keep all 6 N fold rows, or only a maximal independent set found once at a generic state (the dropped rows checked at every point; can follow a spurious branch from the flat state), docs/design/model.md"},
    {"solver.flat_branch",         INT,   SF_KEY_GE,      1, 0,       "1",           NULL, "-", "exact start at the flat state: the stable branch of the tangent cone to follow, by energy (1: lowest), docs/design/start.md"},
    {"solver.linear_solver",       STR,   0,              0, 0,       "dense",       "dense|sparse|mumps|klu", "-", "Newton systems: dense LU (LAPACK) or sparse LU on the compressed Jacobian: sparse = mumps (MUMPS, METIS ordering) or klu (KLU); the pose formulation is always sparse (MUMPS unless klu)"},

    {"output",                     G,     AUTO,           0, 0,       NULL,          NULL, "-", "output settings"},
    {"output.samples",             INT,   RANGE,          2, 1000,    "8",           NULL, "-", "samples across a fold band in VTK shapes"},
    {"output.shapes",              INT,   SF_KEY_GE,      0, 0,       "10",          NULL, "-", "number of shapes written along a path"},
    {"output.shape_every",         INT,   SF_KEY_GE,      0, 0,       "0",           NULL, "-", "also a shape every N points of a path (0: only by p, special points and branch ends)"},
    {"output.plots",               BOOL,  DYN,            0, 0,       "true",        NULL, "-", "draw the plots after the run (default: dynamics yes, equilibrium no)"},
    {"output.plot_folds",          NAMES, 0,              0, 0,       NULL,          NULL, "-", "folds drawn in angles.png: fold names, group names, numbers as text, \"all\""},

    {"analysis",                   G,     AUTO,           0, 0,       NULL,          NULL, "-", "what to compute"},
    {"analysis.type",              STR,   0,              0, 0,       "equilibrium", "equilibrium|dynamics|boundary|none", "-", "equilibrium path, dynamic trajectory, stability boundary in two parameters (docs/guides/stability.md), or nothing"},
    {"analysis.parameter",         STR,   0,              0, 0,       "load",        "load|actuation|displacement", "-", "the parameter p that is varied: load factor, rest angle of an actuation group [rad], or prescribed displacement of a probe [m]"},
    {"analysis.load",              NUM,   NONNEG,         0, 0,       "0.0",         NULL, "-", "load factor held fixed when p is not the load"},
    {"analysis.probe",             STR,   0,              0, 0,       NULL,          NULL, "-", "displacement parameter: the probe whose displacement is prescribed (default: the first probe)"},
    {"analysis.component",         STR,   0,              0, 0,       "z",           "x|y|z", "-", "displacement parameter: the component prescribed"},
    {"analysis.group",             STR,   0,              0, 0,       "",            NULL, "-", "actuation group driven by p (\"\": all groups)"},
    {"analysis.start",             NUM,   0,              0, 0,       "0.0",         NULL, "-", "first value of p"},
    {"analysis.end",               NUM,   0,              0, 0,       NULL,          NULL, "-", "last value of p (default: number of load stages for load, 1 for actuation)"},
    {"analysis.step",              NUM,   POS,            0, 0,       "0.05",        NULL, "-", "initial step"},
    {"analysis.min_step",          NUM,   POS,            0, 0,       "1e-06",       NULL, "-", "smallest step"},
    {"analysis.max_step",          NUM,   POS,            0, 0,       "0.2",         NULL, "-", "largest step"},
    {"analysis.max_steps",         INT,   SF_KEY_GE,      1, 0,       "500",         NULL, "-", "most steps along a branch"},
    {"analysis.step_norm",         STR,   0,              0, 0,       "auto",        "auto|sum|rms", "-", "equilibrium paths: the norm of step, min_step and max_step: sum (the fold coordinates' changes squared, summed, and p's) or rms (their mean instead of their sum, so that a step means the same on a small and a large sheet; the corrector then solves its anchored system first; continuation/README.md); auto: rms above solver.auto_unknowns, else sum"},
    {"analysis.stability",         BOOL,  0,              0, 0,       "true",        NULL, "-", "compute stability along the path"},
    {"analysis.eigenvalues",       INT,   SF_KEY_GE,      0, 0,       "4",           NULL, "-", "lowest eigenvalues of the constrained Hessian reported (at most the number of generalised coordinates)"},
    {"analysis.convergence",       BOOL,  0,              0, 0,       "false",       NULL, "-", "rerun with K+1 shape modes per fold and report the differences (DIR/convergence.tsv)"},
    {"analysis.eigensolver",       STR,   0,              0, 0,       "auto",        "auto|dense|arpack|inertia", "-", "eigenvalues of the constrained Hessian: dense LAPACK (explicit tangent basis), ARPACK shift-invert on the KKT pencil, the inertia of the KKT matrix (MUMPS LDL^T: stability and Morse index, eigenvalues only when ARPACK converges within a bound), or auto (dense up to 200 coordinates, inertia above)"},
    {"analysis.arpack_maxiter",    INT,   SF_KEY_GE,      1, 0,       NULL,          NULL, "-", "ARPACK restarts per attempt (a non-converged attempt is retried with a larger subspace, then another shift); absent: 1000, and at most 10 for the inertia method's one bounded attempt (no default is written, so that absent stays absent)"},
    {"analysis.arpack_attempts",   INT,   SF_KEY_GE,      1, 0,       "4",           NULL, "-", "ARPACK attempts per point before its stability is marked unknown"},
    {"analysis.flat_start",        STR,   0,              0, 0,       "auto",        "auto|limit|direct|sparse|multipliers", "-", "exact closure starting at the flat state: from the limit of the branch (then the penalty homotopy; dense), directly (the engine's tangent at the singular point), sparse (a finite step along the driving's projected response, face poses only; docs/flatstart.md), or multipliers (the closed state of least energy at a given amount of folding by the method of multipliers, either formulation, with a certificate of locking; docs/design/start.md); auto: sparse above solver.auto_unknowns, else multipliers below it, limit above it (when a key keeps the fold formulation) or with analysis.branch_depth >= 1"},
    {"analysis.flat_angle",        NUM,   POS,            0, 0,       "0.05",        NULL, "rad", "sparse flat start: the first step's largest fold angle (halved up to 4 times when the corrector fails)"},
    {"analysis.flat_collapse",     NUM,   SF_KEY_GE | SF_KEY_LT, 0, 1, "0.25",      NULL, "-", "sparse flat start: an extra start of the limit problem (rigid vertex modes, mirror) is left when its largest fold amplitude falls below this fraction of its value at the first penalty stage (0: never)"},
    {"analysis.flat_stall",        INT,   SF_KEY_GE,      0, 0,       "10",          NULL, "-", "sparse flat start: the first start's first penalty stage (eta = 1e-8) is left, and the start made again from eta = 1e-9, after this many Newton iterations in which its fold amplitude had settled (moved by at most 10% a step) and its residual did not fall below half its lowest value since (0: never; docs/flatstart.md)"},
    {"analysis.step_bound",        BOOL,  0,              0, 0,       "true",        NULL, "-", "shorten a step so that it ends between two eigenvalue crossings predicted within it (docs/guides/stability.md)"},
    {"analysis.branch_depth",      INT,   SF_KEY_GE,      0, 0,       "0",           NULL, "-", "levels of branch switching at branch points (0: none)"},
    {"analysis.flat_starts",       INT,   SF_KEY_GE,      1, 0,       "400",         NULL, "-", "exact closure, branch_depth >= 1: Newton starts on the reduced second-order equations at the flat state (every branch of its tangent cone; docs/guides/stability.md)"},
    {"analysis.second",            STR,   0,              0, 0,       NULL,          NULL, "-", "boundary: the second parameter, any numeric study key (defaults.width, materials.fold.E, analysis.load, loads[0].force[0], ...)"},
    {"analysis.second_min",        NUM,   0,              0, 0,       NULL,          NULL, "-", "boundary: smallest value of the second parameter"},
    {"analysis.second_max",        NUM,   0,              0, 0,       NULL,          NULL, "-", "boundary: largest value of the second parameter"},
    {"analysis.second_step",       NUM,   POS,            0, 0,       "0.02",        NULL, "-", "boundary: initial step along the curve (arclength in the second parameter relative to its study value, the path parameter and the fold angles)"},
    {"analysis.second_max_step",   NUM,   POS,            0, 0,       "0.1",         NULL, "-", "boundary: largest step along the curve"},
    {"analysis.from",              STR,   0,              0, 0,       "any",         "any|LP|BP", "-", "boundary: continue the first limit point (LP), branch point (BP) or either that the path meets"},
    {"analysis.report",            STR,   0,              0, 0,       NULL,          NULL, "-", "probe reported against p (default: the first probe)"},
    {"analysis.duration",          NUM,   POS | DYN,      0, 0,       NULL,          NULL, "s", "length of the trajectory (required for dynamics)"},
    {"analysis.damping",           NUM,   POS | DYN,      0, 0,       "1.0",         NULL, "J s", "damping coefficient of every fold angle without folds[].damping"},
    {"analysis.inertia",           BOOL,  DYN,            0, 0,       "false",       NULL, "-", "include inertia (otherwise overdamped, M = 0)"},
    {"analysis.settle_tolerance",  NUM,   POS | DYN,      0, 0,       "1e-08",       NULL, "rad/s", "max |q'| below which the trajectory has settled (once every history has ended)"},
    {"analysis.schedule",          LIST,  0,              0, 0,       NULL,          NULL, "-", "p(t), piecewise linear (default: start to end over duration)"},
    {"analysis.schedule[]",        G,     0,              0, 0,       NULL,          NULL, "-", "one point of the schedule"},
    {"analysis.schedule[].t",      NUM,   REQ | NONNEG,   0, 0,       NULL,          NULL, "s", "time"},
    {"analysis.schedule[].value",  NUM,   REQ,            0, 0,       NULL,          NULL, "-", "value of p at t"},
    {"analysis.load_schedule",     LIST,  0,              0, 0,       NULL,          NULL, "-", "dynamics: load factor over time, piecewise linear, when p is not the load (default: analysis.load throughout)"},
    {"analysis.load_schedule[]",   G,     0,              0, 0,       NULL,          NULL, "-", "one point of the load schedule"},
    {"analysis.load_schedule[].t", NUM,   REQ | NONNEG,   0, 0,       NULL,          NULL, "s", "time"},
    {"analysis.load_schedule[].value", NUM, REQ | NONNEG, 0, 0,       NULL,          NULL, "-", "load factor at t"},
    {"analysis.initial",           STR,   DYN,            0, 0,       "equilibrium", "equilibrium|flat", "-", "dynamics: start at rest in the equilibrium at t = 0, or at rest in the flat state"},
    {"analysis.tolerance",         NUM,   POS | DYN,      0, 0,       "1e-06",       NULL, "-", "dynamics: relative local error tolerance of the integrator (IDA)"},
    {"analysis.max_time_steps",    INT,   SF_KEY_GE | DYN, 1, 0,      "100000",      NULL, "-", "dynamics: most integrator steps"},

    /* reference data compared with the path (compare.c, docs/reference/study-keys.md) */
    {"references",                 LIST,  0,              0, 0,       NULL,          NULL, "-", "reference data files compared with the computed path"},
    {"references[]",               G,     0,              0, 0,       NULL,          NULL, "-", "one reference file"},
    {"references[].name",          STR,   IDENT,          0, 0,       NULL,          NULL, "-", "name in compare.tsv and messages (default: the file name)"},
    {"references[].file",          STR,   REQ,            0, 0,       NULL,          NULL, "-", "CSV file with a provenance header (beside the study, in $SMOOTHFOLD_DATA, or in shared/data above the study)"},
    {"references[].abscissa",      G,     REQ,            0, 0,       NULL,          NULL, "-", "the column that locates a reference row on the path"},
    {"references[].abscissa.column", STR, REQ,            0, 0,       NULL,          NULL, "-", "column name in the file"},
    {"references[].abscissa.quantity", STR, 0,            0, 0,       "p",           NULL, "-", "study quantity it matches (p, load, probe1_uz, tip_uz, theta1, energy)"},
    {"references[].abscissa.scale", NUM,  0,              0, 0,       "1.0",         NULL, "-", "quantity = scale * column value (unit or sign change; not 0)"},
    {"references[].solve",         BOOL,  0,              0, 0,       "true",        NULL, "-", "abscissa p (or load): solve the equilibrium at each reference value (false: interpolate between computed points)"},
    {"references[].columns",       LIST,  REQ,            0, 0,       NULL,          NULL, "-", "the columns compared with study quantities"},
    {"references[].columns[]",     G,     0,              0, 0,       NULL,          NULL, "-", "one compared column"},
    {"references[].columns[].column", STR, REQ,           0, 0,       NULL,          NULL, "-", "column name in the file"},
    {"references[].columns[].quantity", STR, 0,           0, 0,       NULL,          NULL, "-", "study quantity it matches (default: the column name)"},
    {"references[].columns[].scale", NUM, 0,              0, 0,       "1.0",         NULL, "-", "quantity = scale * column value (not 0)"},
    {"references[].columns[].measure", STR, 0,            0, 0,       "scaled",      "scaled|relative|absolute", "-", "error measure: |d| / max |reference|, |d| / |reference| pointwise, or |d| in the quantity's unit"},
    {"references[].columns[].norm", STR,  0,              0, 0,       "max",         "max|rms|end", "-", "which error the tolerance bounds: largest, root mean square, or at the last compared row"},
    {"references[].columns[].tolerance", NUM, POS,        0, 0,       NULL,          NULL, "-", "bound on that error (absent: report only); exceeded, the run exits with status 6"},

    /* smoothfold sweep (src/analysis/sweep/sweep.h); `run` ignores the group */
    {"sweep",                      G,     0,              0, 0,       NULL,          NULL, "-", "parameter sweep: the variants `smoothfold sweep` runs (docs/guides/sweeps.md)"},
    {"sweep.vary",                 NAMES, REQ,            0, 0,       NULL,          NULL, "-", "varied keys as for --vary: [\"KEY=V1,V2,...\", \"KEY=START:STOP:N\"]"},
    {"sweep.mode",                 STR,   0,              0, 0,       "product",     "product|list", "-", "every combination of the values, or a list (variant i takes the i-th value of every key)"},
    {"sweep.map",                  STR,   0,              0, 0,       NULL,          NULL, "-", "sweep.tsv column drawn over the first two varied keys by `smoothfold plot` (default: lp_p, else bp_p, else end_probe1_uz)"},
};

#undef G
#undef NAMED
#undef LIST
#undef NUM
#undef INT
#undef STR
#undef BOOL
#undef V2
#undef V3
#undef B3
#undef NAMES
#undef REQ
#undef POS
#undef NONNEG
#undef IDENT
#undef AUTO
#undef DYN
#undef RANGE

#define NSCHEMA ((int)(sizeof schema / sizeof schema[0]))

const sf_study_key *sf_study_schema(int *n)
{
    if (n) *n = NSCHEMA;
    return schema;
}

const sf_study_key *st_schema_find(const char *pattern)
{
    for (int i = 0; i < NSCHEMA; i++)
        if (strcmp(schema[i].path, pattern) == 0) return &schema[i];
    return NULL;
}

/* Is entry a direct child of pattern?  On success *name is the member
 * name (or "[]" / "*"). */
int st_schema_is_child(const sf_study_key *k, const char *pattern,
                       const char **name)
{
    size_t lp = strlen(pattern);
    const char *rest;
    if (lp == 0) {
        rest = k->path;
    } else {
        if (strncmp(k->path, pattern, lp) != 0) return 0;
        rest = k->path + lp;
        if (strcmp(rest, "[]") == 0) { *name = rest; return 1; }
        if (rest[0] != '.') return 0;
        rest++;
    }
    if (!rest[0] || strchr(rest, '.') || strchr(rest, '[')) return 0;
    *name = rest;
    return 1;
}

/* Candidates for a suggestion: children of pattern; returns count. */
static int schema_children(const char *pattern, const char **out, int max)
{
    int n = 0;
    for (int i = 0; i < NSCHEMA && n < max; i++) {
        const char *name;
        if (st_schema_is_child(&schema[i], pattern, &name)
            && strcmp(name, "*") != 0 && strcmp(name, "[]") != 0)
            out[n++] = name;
    }
    return n;
}

/* Suggestion for an unknown key name under pattern: a sibling, else a
 * full path elsewhere in the schema whose last name is close. */
const char *st_suggest_key(const char *pattern, const char *name,
                           char *buf, size_t n)
{
    const char *cand[NSCHEMA];
    int nc = schema_children(pattern, cand, NSCHEMA);
    const char *sg = sf_study_suggest(name, nc, cand);
    if (sg) { snprintf(buf, n, "%s", sg); return buf; }
    /* elsewhere: last component */
    const char *last[NSCHEMA];
    int idx[NSCHEMA], nl = 0;
    for (int i = 0; i < NSCHEMA; i++) {
        const char *dot = strrchr(schema[i].path, '.');
        const char *l = dot ? dot + 1 : schema[i].path;
        if (strchr(l, '[') || strcmp(l, "*") == 0) continue;
        idx[nl] = i;
        last[nl++] = l;
    }
    int exact = -1;
    for (int i = 0; i < nl; i++)
        if (strcmp(last[i], name) == 0) { exact = idx[i]; break; }
    if (exact < 0) {
        const char *s2 = sf_study_suggest(name, nl, last);
        if (s2)
            for (int i = 0; i < nl; i++)
                if (last[i] == s2) { exact = idx[i]; break; }
    }
    if (exact < 0) return NULL;
    /* render the pattern readably: "*" -> NAME, "[]" -> [i] */
    size_t o = 0;
    for (const char *p = schema[exact].path; *p && o + 8 < n; p++) {
        if (*p == '*') { memcpy(buf + o, "NAME", 4); o += 4; }
        else if (p[0] == '[' && p[1] == ']') { memcpy(buf + o, "[i]", 3); o += 3; p++; }
        else buf[o++] = *p;
    }
    buf[o] = '\0';
    return buf;
}

void sf_study_free(sf_study *s)
{
    if (!s) return;
    if (s->cfg) {
        config_destroy((config_t *)s->cfg);
        free(s->cfg);
    }
    free(s->vertices);
    free(s->outline);
    free(s->folds);
    free(s->facet_edges);
    free(s->materials);
    free(s->loads);
    free(s->groups);
    free(s->supports);
    free(s->probes);
    memset(s, 0, sizeof *s);
}

static void free_hook(void *p) { free(p); }

static char *read_all(const char *path, int *errnum)
{
    FILE *f = fopen(path, "rb");
    if (!f) { *errnum = errno; return NULL; }
    size_t cap = 8192, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        size_t r = fread(buf + n, 1, cap - n - 1, f);
        n += r;
        if (n + 1 < cap) break;
        char *nb = realloc(buf, cap * 2);
        if (!nb) { free(buf); buf = NULL; break; }
        buf = nb;
        cap *= 2;
    }
    if (buf) buf[n] = '\0';
    if (ferror(f)) { *errnum = errno ? errno : EIO; free(buf); buf = NULL; }
    else if (!buf) *errnum = ENOMEM;
    fclose(f);
    return buf;
}

int sf_study_load(const char *path, int nset, const char *const *sets,
                  sf_study *s, sf_error *err)
{
    int rc;
    memset(s, 0, sizeof *s);
    if (!path) return sf_fail(err, SF_EINTERNAL, "sf_study_load: no path");
    if (strlen(path) >= sizeof s->path)
        return sf_fail(err, SF_EINPUT, "%.60s...: path too long", path);
    snprintf(s->path, sizeof s->path, "%s", path);

    /* read the text once for the integer range check (libconfig 1.5 wraps
     * integer literals beyond int silently) */
    int en = 0;
    char *text = read_all(path, &en);
    if (!text)
        return sf_fail(err, en == ENOMEM ? SF_ENOMEM : SF_EIO, "%s: cannot read: %s", path, strerror(en));

    config_t *cfg = calloc(1, sizeof *cfg);
    if (!cfg) { free(text); return sf_fail(err, SF_ENOMEM, "out of memory"); }
    config_init(cfg);
    config_set_destructor(cfg, free_hook);
    s->cfg = cfg;
    {   /* @include relative to the study's folder, and confined to it
         * (study_include.c) */
        char dir[1024];
        snprintf(dir, sizeof dir, "%s", path);
        char *sl = strrchr(dir, '/');
        if (sl) sl[sl == dir ? 1 : 0] = '\0';
        else snprintf(dir, sizeof dir, ".");
        config_set_include_dir(cfg, dir);
        rc = st_check_includes(path, text, dir, err);
        if (rc) { free(text); sf_study_free(s); return rc; }
    }
    if (!config_read_file(cfg, path)) {
        if (config_error_type(cfg) == CONFIG_ERR_FILE_IO) {
            rc = sf_fail(err, SF_EIO, "%s: cannot read: %s", path, config_error_text(cfg));
        } else {
            const char *f = config_error_file(cfg);
            const char *t = config_error_text(cfg);
            const char *hnt = "";
            if (t && strstr(t, "mismatched element type"))
                hnt = " (write every number of an array the same way, e.g. [0.0, 0.015], not [0, 0.015])";
            else if (t && strstr(t, "duplicate setting"))
                hnt = " (each key, and each vertex or material name, may be given only once)";
            rc = sf_fail(err, SF_EINPUT, "%s:%d: %s%s", f ? f : path, config_error_line(cfg), t ? t : "syntax error", hnt);
        }
        free(text);
        sf_study_free(s);
        return rc;
    }
    {
        char tok[64];
        int line = st_find_int_overflow(text, tok, sizeof tok);
        free(text);
        if (line) {
            sf_study_free(s);
            return sf_fail(err, SF_EINPUT,
                           "%s:%d: integer %s is out of range (libconfig would wrap it): write it with a decimal point or an exponent",
                           path, line, tok);
        }
    }

    for (int i = 0; i < nset; i++) {
        rc = st_apply_set(cfg, sets[i], err);
        if (rc) { sf_study_free(s); return rc; }
    }

    rc = st_check_group(s, err, config_root_setting(cfg), "");
    if (!rc) rc = st_fill(s, cfg, err);
    if (!rc) rc = st_materialize(s, cfg, err);
    if (!rc) rc = sf_study_check_assignments(s, err);   /* assignment.c */
    if (!rc) rc = sf_study_add_facets(s, err);          /* facets.c: faces.bending */
    if (rc) {
        sf_study_free(s);
        return rc;
    }
    return SF_OK;
}

int sf_study_vertex_index(const sf_study *s, const char *name)
{
    return s->nvertices ? st_find_name(name, s->vertices[0].name, sizeof(sf_vertex), s->nvertices) : -1;
}

int sf_study_fold_index(const sf_study *s, const char *name)
{
    if (!name || !name[0]) return -1;
    return s->nfolds ? st_find_name(name, s->folds[0].name, sizeof(sf_fold_def), s->nfolds) : -1;
}

int sf_study_material_index(const sf_study *s, const char *name)
{
    return s->nmaterials ? st_find_name(name, s->materials[0].name, sizeof(sf_material), s->nmaterials) : -1;
}

int sf_study_group_index(const sf_study *s, const char *name)
{
    return s->ngroups ? st_find_name(name, s->groups[0].name, sizeof(sf_group), s->ngroups) : -1;
}

int sf_study_probe_index(const sf_study *s, const char *name)
{
    return s->nprobes ? st_find_name(name, s->probes[0].name, sizeof(sf_probe), s->nprobes) : -1;
}
