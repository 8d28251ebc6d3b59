/* study.c - the study file: schema, reader, --set overrides, checks, writer
 * and accessors (study.h, docs/study-format.md).
 *
 * Everything a study may contain is listed in ONE table, `schema` below:
 * path pattern, type, bounds, default, unit and a line of documentation.
 * The generic checker walks the libconfig tree against it (unknown keys,
 * types, finiteness, bounds, required keys, choices); the semantic pass then
 * resolves names and fills the sf_study of pattern.h.  To add a key for a
 * new module, add a row (and document it in docs/study-format.md; the test
 * checks that every row is mentioned there).
 *
 * Path patterns: "a.b" a member of group a; "a.*" any member of a group of
 * free names (vertices, materials); "a[]" each element of list a.
 */
#include "study.h"

#include <ctype.h>
#include <errno.h>
#include <libconfig.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------- */
/* The schema                                                              */
/* ---------------------------------------------------------------------- */

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
    {"faces.material",             STR,   REQ,            0, 0,       NULL,          NULL, "-", "material of the faces (thickness, density; needed for gravity)"},

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
    {"solver.quadrature",          INT,   RANGE,          1, 64,      "24",          NULL, "-", "Gauss-Legendre points across a fold"},
    {"solver.tolerance",           NUM,   POS,            0, 0,       "1e-10",       NULL, "-", "Newton tolerance (scaled residual norm)"},
    {"solver.linear_solver",       STR,   0,              0, 0,       "dense",       "dense|sparse", "-", "Newton systems: dense LU (LAPACK-style, SUNDIALS dense) or sparse LU (KLU on the compressed Jacobian)"},

    {"output",                     G,     AUTO,           0, 0,       NULL,          NULL, "-", "output settings"},
    {"output.samples",             INT,   RANGE,          2, 1000,    "8",           NULL, "-", "samples across a fold band in VTK shapes"},
    {"output.shapes",              INT,   SF_KEY_GE,      0, 0,       "10",          NULL, "-", "number of shapes written along a path"},

    {"analysis",                   G,     AUTO,           0, 0,       NULL,          NULL, "-", "what to compute"},
    {"analysis.type",              STR,   0,              0, 0,       "equilibrium", "equilibrium|dynamics|none", "-", "equilibrium path, dynamic trajectory, or nothing"},
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
    {"analysis.stability",         BOOL,  0,              0, 0,       "true",        NULL, "-", "compute stability along the path"},
    {"analysis.eigenvalues",       INT,   SF_KEY_GE,      0, 0,       "4",           NULL, "-", "lowest eigenvalues of the constrained Hessian reported"},
    {"analysis.eigensolver",       STR,   0,              0, 0,       "auto",        "auto|dense|arpack", "-", "eigenvalues of the constrained Hessian: dense LAPACK (explicit tangent basis), ARPACK shift-invert on the KKT pencil, or auto (dense up to 200 coordinates)"},
    {"analysis.branch_depth",      INT,   SF_KEY_GE,      0, 0,       "0",           NULL, "-", "levels of branch switching at branch points (0: none)"},
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

    /* reference data compared with the path (compare.c, docs/study-format.md) */
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

    /* smoothfold sweep (src/analysis/sweep.h); `run` ignores the group */
    {"sweep",                      G,     0,              0, 0,       NULL,          NULL, "-", "parameter sweep: the variants `smoothfold sweep` runs (docs/sweep.md)"},
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

static const sf_study_key *schema_find(const char *pattern)
{
    for (int i = 0; i < NSCHEMA; i++)
        if (strcmp(schema[i].path, pattern) == 0) return &schema[i];
    return NULL;
}

/* Is entry a direct child of pattern?  On success *name is the member
 * name (or "[]" / "*"). */
static int schema_is_child(const sf_study_key *k, const char *pattern,
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

/* ---------------------------------------------------------------------- */
/* Small helpers                                                           */
/* ---------------------------------------------------------------------- */

static int osa_distance(const char *a, const char *b)
{
    enum { M = 64 };
    int la = (int)strlen(a), lb = (int)strlen(b);
    if (la > M - 1) la = M - 1;
    if (lb > M - 1) lb = M - 1;
    int d[M][M];
    for (int i = 0; i <= la; i++) d[i][0] = i;
    for (int j = 0; j <= lb; j++) d[0][j] = j;
    for (int i = 1; i <= la; i++)
        for (int j = 1; j <= lb; j++) {
            int ca = tolower((unsigned char)a[i - 1]);
            int cb = tolower((unsigned char)b[j - 1]);
            int cost = ca != cb;
            int v = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < v) v = d[i][j - 1] + 1;
            if (d[i - 1][j - 1] + cost < v) v = d[i - 1][j - 1] + cost;
            if (i > 1 && j > 1 && ca == tolower((unsigned char)b[j - 2])
                && tolower((unsigned char)a[i - 2]) == cb
                && d[i - 2][j - 2] + 1 < v)
                v = d[i - 2][j - 2] + 1;
            d[i][j] = v;
        }
    return d[la][lb];
}

const char *sf_study_suggest(const char *word, int ncand,
                             const char *const *cand)
{
    if (!word || !word[0]) return NULL;
    int len = (int)strlen(word);
    int maxd = len <= 3 ? 1 : len <= 6 ? 2 : 3;
    const char *best = NULL;
    int bestd = INT_MAX;
    for (int i = 0; i < ncand; i++) {
        if (!cand[i] || !cand[i][0]) continue;
        int d = osa_distance(word, cand[i]);
        if (d < bestd) { bestd = d; best = cand[i]; }
    }
    if (!best || bestd > maxd || bestd >= len) return NULL;
    if (strcmp(best, word) == 0) return NULL;
    return best;
}

/* " (did you mean 'x'?)" or "" */
static const char *hint(char *buf, size_t n, const char *sugg)
{
    if (sugg) snprintf(buf, n, " (did you mean '%s'?)", sugg);
    else buf[0] = '\0';
    return buf;
}

static int is_ident(const char *t)
{
    if (!(isalpha((unsigned char)t[0]) || t[0] == '_')) return 0;
    for (const char *p = t + 1; *p; p++)
        if (!(isalnum((unsigned char)*p) || *p == '_' || *p == '-')) return 0;
    return 1;
}

static int is_filesafe(const char *t)
{
    if (!t[0]) return 0;
    for (const char *p = t; *p; p++)
        if (!(isalnum((unsigned char)*p) || *p == '_' || *p == '-' || *p == '.'))
            return 0;
    return strcmp(t, ".") != 0 && strcmp(t, "..") != 0;
}

static void copy_name(char *dst, const char *src)
{
    snprintf(dst, SF_NAME_MAX, "%s", src);
}

/* dst = a sep b, truncated to n (no format-truncation warnings) */
static void join3(char *dst, size_t n, const char *a, const char *sep,
                  const char *b)
{
    size_t la = strlen(a), ls = strlen(sep), lb = strlen(b), o = 0;
    if (n == 0) return;
    if (la > n - 1) la = n - 1;
    memmove(dst, a, la);
    o = la;
    if (ls > n - 1 - o) ls = n - 1 - o;
    memcpy(dst + o, sep, ls);
    o += ls;
    if (lb > n - 1 - o) lb = n - 1 - o;
    memcpy(dst + o, b, lb);
    dst[o + lb] = '\0';
}

static char *xstrdup(const char *t)
{
    size_t n = strlen(t) + 1;
    char *p = malloc(n);
    if (p) memcpy(p, t, n);
    return p;
}

/* ---------------------------------------------------------------------- */
/* Locations and key paths                                                 */
/* ---------------------------------------------------------------------- */

static void where(const sf_study *s, const config_setting_t *st, char *buf,
                  size_t n)
{
    for (const config_setting_t *p = st; p; p = p->parent)
        if (p->hook) { snprintf(buf, n, "%s", (const char *)p->hook); return; }
    const config_setting_t *p = st;
    while (p && p->parent && p->line == 0) p = p->parent;
    if (p && p->parent && p->line > 0) {
        const char *f = config_setting_source_file(p);
        snprintf(buf, n, "%s:%u", f ? f : s->path, p->line);
    } else {
        snprintf(buf, n, "%s", s->path);
    }
}

static void keypath(const config_setting_t *st, char *buf, size_t n)
{
    if (!st || !st->parent) { buf[0] = '\0'; return; }
    keypath(st->parent, buf, n);
    size_t l = strlen(buf);
    if (l >= n) return;
    if (st->parent->type == CONFIG_TYPE_GROUP)
        snprintf(buf + l, n - l, "%s%s", l ? "." : "", st->name);
    else
        snprintf(buf + l, n - l, "[%d]", config_setting_index(st));
}

/* Record "<where>: <keypath>: <message>" (keypath omitted when withpath is
 * 0 or the setting is the root). */
static int vfailat2(const sf_study *s, sf_error *err, int code,
                    const config_setting_t *locst, const config_setting_t *st,
                    int withpath, const char *fmt, va_list ap)
{
    char loc[1200], kp[512], msg[1024];
    where(s, locst, loc, sizeof loc);
    keypath(st, kp, sizeof kp);
    vsnprintf(msg, sizeof msg, fmt, ap);
    if (withpath && kp[0])
        return sf_fail(err, code, "%s: %s: %s", loc, kp, msg);
    return sf_fail(err, code, "%s: %s", loc, msg);
}

static int vfailat(const sf_study *s, sf_error *err, int code,
                   const config_setting_t *st, int withpath, const char *fmt,
                   va_list ap)
{
    return vfailat2(s, err, code, st, st, withpath, fmt, ap);
}

/* "<where of locst>: <keypath of st>: <message>" */
__attribute__((format(printf, 5, 6)))
static int bad2(const sf_study *s, sf_error *err, const config_setting_t *locst,
                const config_setting_t *st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int r = vfailat2(s, err, SF_EINPUT, locst, st, 1, fmt, ap);
    va_end(ap);
    return r;
}

__attribute__((format(printf, 4, 5)))
static int bad(const sf_study *s, sf_error *err, const config_setting_t *st,
               const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int r = vfailat(s, err, SF_EINPUT, st, 1, fmt, ap);
    va_end(ap);
    return r;
}

__attribute__((format(printf, 4, 5)))
static int bad_raw(const sf_study *s, sf_error *err,
                   const config_setting_t *st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int r = vfailat(s, err, SF_EINPUT, st, 0, fmt, ap);
    va_end(ap);
    return r;
}

static const char *type_name(int t)
{
    switch (t) {
    case CONFIG_TYPE_GROUP: return "a group";
    case CONFIG_TYPE_INT:
    case CONFIG_TYPE_INT64: return "an integer";
    case CONFIG_TYPE_FLOAT: return "a number";
    case CONFIG_TYPE_STRING: return "a string";
    case CONFIG_TYPE_BOOL: return "a boolean";
    case CONFIG_TYPE_ARRAY: return "an array";
    case CONFIG_TYPE_LIST: return "a list";
    default: return "nothing";
    }
}

static const char *key_type_name(int t)
{
    switch (t) {
    case SF_KEY_GROUP:
    case SF_KEY_NAMED: return "a group { ... }";
    case SF_KEY_LIST: return "a list ( ... )";
    case SF_KEY_NUMBER: return "a number";
    case SF_KEY_INT: return "an integer";
    case SF_KEY_STRING: return "a string";
    case SF_KEY_BOOL: return "true or false";
    case SF_KEY_VEC2: return "[x, y]";
    case SF_KEY_VEC3: return "[x, y, z]";
    case SF_KEY_BOOL3: return "[bool, bool, bool]";
    case SF_KEY_NAMES: return "an array of names [\"a\", \"b\", ...]";
    default: return "?";
    }
}

/* A short rendering of a value for "got ..." */
static const char *show(const config_setting_t *st, char *buf, size_t n)
{
    switch (st->type) {
    case CONFIG_TYPE_INT: snprintf(buf, n, "%d", st->value.ival); break;
    case CONFIG_TYPE_INT64: snprintf(buf, n, "%lld", st->value.llval); break;
    case CONFIG_TYPE_FLOAT:
        snprintf(buf, n, "%g", st->value.fval);
        if (!strpbrk(buf, ".eni") && strlen(buf) + 3 <= n) strcat(buf, ".0");
        break;
    case CONFIG_TYPE_BOOL: snprintf(buf, n, "%s", st->value.ival ? "true" : "false"); break;
    case CONFIG_TYPE_STRING: snprintf(buf, n, "\"%.40s%s\"", st->value.sval ? st->value.sval : "",
                                      st->value.sval && strlen(st->value.sval) > 40 ? "..." : "");
        break;
    default: snprintf(buf, n, "%s", type_name(st->type)); break;
    }
    return buf;
}

static int is_num(const config_setting_t *st)
{
    return st->type == CONFIG_TYPE_INT || st->type == CONFIG_TYPE_INT64
        || st->type == CONFIG_TYPE_FLOAT;
}

static double numval(const config_setting_t *st)
{
    switch (st->type) {
    case CONFIG_TYPE_INT: return st->value.ival;
    case CONFIG_TYPE_INT64: return (double)st->value.llval;
    case CONFIG_TYPE_FLOAT: return st->value.fval;
    default: return NAN;
    }
}

static config_setting_t *mem(const config_setting_t *g, const char *name)
{
    if (!g || g->type != CONFIG_TYPE_GROUP) return NULL;
    return config_setting_get_member(g, name);
}

/* ---------------------------------------------------------------------- */
/* Integer literals libconfig 1.5 would silently wrap                      */
/* ---------------------------------------------------------------------- */

/* Finds the first decimal integer literal (no '.', exponent or L suffix)
 * beyond the range of int.  Returns its line (>= 1) or 0. */
static int find_int_overflow(const char *p, char *tok, size_t ntok)
{
    int line = 1;
    while (*p) {
        unsigned char c = (unsigned char)*p;
        if (c == '\n') { line++; p++; }
        else if (c == '#' || (c == '/' && p[1] == '/')) {
            while (*p && *p != '\n') p++;
        } else if (c == '/' && p[1] == '*') {
            p += 2;
            while (*p && !(p[0] == '*' && p[1] == '/')) { if (*p == '\n') line++; p++; }
            if (*p) p += 2;
        } else if (c == '"') {
            p++;
            while (*p && *p != '"') {
                if (*p == '\\' && p[1]) p++;
                if (*p == '\n') line++;
                p++;
            }
            if (*p) p++;
        } else if (isalpha(c) || c == '_' || c == '*' || c == '@') {
            while (isalnum((unsigned char)*p) || *p == '_' || *p == '-' || *p == '*') p++;
        } else if (isdigit(c) || (c == '.' && isdigit((unsigned char)p[1]))) {
            const char *start = p;
            int hex = (p[0] == '0' && (p[1] == 'x' || p[1] == 'X'));
            int flt = 0;
            while (*p) {
                if (isalnum((unsigned char)*p) || *p == '.') {
                    if (!hex && (*p == '.' || *p == 'e' || *p == 'E')) flt = 1;
                    p++;
                } else if ((*p == '+' || *p == '-') && !hex && (p[-1] == 'e' || p[-1] == 'E')) {
                    p++;
                } else {
                    break;
                }
            }
            size_t len = (size_t)(p - start);
            if (hex || flt || start[len - 1] == 'L') continue;
            const char *d = start;
            while (*d == '0' && d < p - 1) d++;
            size_t nd = (size_t)(p - d);
            if (nd > 10 || (nd == 10 && strncmp(d, "2147483647", 10) > 0)) {
                snprintf(tok, ntok, "%.*s", (int)(len < 40 ? len : 40), start);
                return line;
            }
        } else {
            p++;
        }
    }
    return 0;
}

/* ---------------------------------------------------------------------- */
/* Copying values (for --set)                                              */
/* ---------------------------------------------------------------------- */

static int copy_value(config_setting_t *dst, const config_setting_t *src)
{
    switch (src->type) {
    case CONFIG_TYPE_INT: return config_setting_set_int(dst, src->value.ival) ? 0 : -1;
    case CONFIG_TYPE_INT64: return config_setting_set_int64(dst, src->value.llval) ? 0 : -1;
    case CONFIG_TYPE_FLOAT: return config_setting_set_float(dst, src->value.fval) ? 0 : -1;
    case CONFIG_TYPE_BOOL: return config_setting_set_bool(dst, src->value.ival) ? 0 : -1;
    case CONFIG_TYPE_STRING: return config_setting_set_string(dst, src->value.sval) ? 0 : -1;
    case CONFIG_TYPE_GROUP:
    case CONFIG_TYPE_ARRAY:
    case CONFIG_TYPE_LIST: {
        int n = config_setting_length(src);
        for (int i = 0; i < n; i++) {
            const config_setting_t *c = config_setting_get_elem(src, (unsigned)i);
            config_setting_t *d = config_setting_add(
                dst, src->type == CONFIG_TYPE_GROUP ? c->name : NULL, c->type);
            if (!d || copy_value(d, c)) return -1;
        }
        return 0;
    }
    default: return -1;
    }
}

static void set_hook(config_setting_t *st, const char *text)
{
    free(st->hook);   /* an earlier --set of the same key */
    st->hook = xstrdup(text);
}

/* ---------------------------------------------------------------------- */
/* Key paths: parse and resolve                                            */
/* ---------------------------------------------------------------------- */

enum { COMP_NAME, COMP_INDEX, COMP_SELECT };
typedef struct comp { int kind; char text[SF_NAME_MAX]; long index; } comp;

/* "a.b[2].c[name]" -> components.  Returns count or -1. */
static int parse_path(const char *path, comp *c, int maxc, char *msg, size_t n)
{
    int nc = 0;
    const char *p = path;
    if (!*p) { snprintf(msg, n, "empty key"); return -1; }
    while (*p) {
        if (nc == maxc) { snprintf(msg, n, "key path too deep"); return -1; }
        if (*p == '[') {
            const char *e = strchr(p, ']');
            if (!e || e == p + 1) { snprintf(msg, n, "bad selector in '%s' (use [index] or [name])", path); return -1; }
            size_t len = (size_t)(e - p - 1);
            if (len >= SF_NAME_MAX) { snprintf(msg, n, "selector too long in '%s'", path); return -1; }
            memcpy(c[nc].text, p + 1, len);
            c[nc].text[len] = '\0';
            char *end;
            errno = 0;
            long v = strtol(c[nc].text, &end, 10);
            if (isdigit((unsigned char)c[nc].text[0]) && *end == '\0' && errno == 0) {
                c[nc].kind = COMP_INDEX;
                c[nc].index = v;
            } else {
                c[nc].kind = COMP_SELECT;
            }
            nc++;
            p = e + 1;
            if (*p == '.') { p++; if (!*p || *p == '.') { snprintf(msg, n, "bad key '%s'", path); return -1; } }
            else if (*p && *p != '[') { snprintf(msg, n, "bad key '%s' (expected '.' or '[' after ']')", path); return -1; }
        } else {
            size_t len = strcspn(p, ".[");
            if (len == 0 || len >= SF_NAME_MAX) { snprintf(msg, n, "bad key '%s'", path); return -1; }
            memcpy(c[nc].text, p, len);
            c[nc].text[len] = '\0';
            c[nc].kind = COMP_NAME;
            nc++;
            p += len;
            if (*p == '.') { p++; if (!*p || *p == '.') { snprintf(msg, n, "bad key '%s'", path); return -1; } }
        }
    }
    return nc;
}

/* Candidates for a suggestion: children of pattern; returns count. */
static int schema_children(const char *pattern, const char **out, int max)
{
    int n = 0;
    for (int i = 0; i < NSCHEMA && n < max; i++) {
        const char *name;
        if (schema_is_child(&schema[i], pattern, &name)
            && strcmp(name, "*") != 0 && strcmp(name, "[]") != 0)
            out[n++] = name;
    }
    return n;
}

/* Suggestion for an unknown key name under pattern: a sibling, else a
 * full path elsewhere in the schema whose last name is close. */
static const char *suggest_key(const char *pattern, const char *name,
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

typedef struct resolved {
    config_setting_t *parent;   /* existing parent (NULL if absent) */
    config_setting_t *node;     /* the setting, NULL if absent */
    const sf_study_key *key;    /* its schema entry */
    char name[SF_NAME_MAX];     /* member name when the last component is a name */
    char pattern[512];
} resolved;

/* Resolve a key path in cfg.  create: make missing groups on the way
 * (their top-most one gets the hook text).  Returns 0, or -1 with msg. */
static int resolve(config_t *cfg, const char *path, int create,
                   const char *hooktext, resolved *r, char *msg, size_t n)
{
    comp c[16];
    int nc = parse_path(path, c, 16, msg, n);
    if (nc < 0) return -1;
    config_setting_t *cur = config_root_setting(cfg);
    const sf_study_key *ck = NULL;   /* entry of cur, NULL = root group */
    char pat[512] = "", shown[512] = "";
    int hooked = 0;
    memset(r, 0, sizeof *r);
    for (int i = 0; i < nc; i++) {
        int last = i == nc - 1;
        int ctype = ck ? ck->type : SF_KEY_GROUP;
        char npat[512];
        if (c[i].kind == COMP_NAME) {
            if (ctype == SF_KEY_GROUP) {
                join3(npat, sizeof npat, pat, pat[0] ? "." : "", c[i].text);
                const sf_study_key *k = schema_find(npat);
                if (!k) {
                    char sb[512], h[600];
                    const char *sg = suggest_key(pat, c[i].text, sb, sizeof sb);
                    if (shown[0])
                        snprintf(msg, n, "unknown key '%s' in %s%s", c[i].text, shown, hint(h, sizeof h, sg));
                    else
                        snprintf(msg, n, "unknown key '%s' at top level%s", c[i].text, hint(h, sizeof h, sg));
                    return -1;
                }
                ck = k;
            } else if (ctype == SF_KEY_NAMED) {
                join3(npat, sizeof npat, pat, ".*", "");
                ck = schema_find(npat);
            } else if (ctype == SF_KEY_LIST) {
                snprintf(msg, n, "%s is a list: select an element with [index] or [name]", shown);
                return -1;
            } else {
                snprintf(msg, n, "%s is %s and has no keys (set it whole)", shown, key_type_name(ctype));
                return -1;
            }
            if (!ck) { snprintf(msg, n, "'%s' is not in the schema", npat); return -1; }
            config_setting_t *child = cur ? config_setting_get_member(cur, c[i].text) : NULL;
            join3(pat, sizeof pat, npat, "", "");
            size_t ls = strlen(shown);
            snprintf(shown + ls, sizeof shown - ls, "%s%s", ls ? "." : "", c[i].text);
            if (last) {
                r->parent = cur;
                r->node = child;
                snprintf(r->name, sizeof r->name, "%s", c[i].text);
                break;
            }
            if (!child && create && cur) {
                if (ck->type != SF_KEY_GROUP && ck->type != SF_KEY_NAMED) {
                    snprintf(msg, n, "%s is absent: set it whole first", shown);
                    return -1;
                }
                if (cur->type != CONFIG_TYPE_GROUP) {
                    snprintf(msg, n, "%s is not a group", shown);
                    return -1;
                }
                child = config_setting_add(cur, c[i].text, CONFIG_TYPE_GROUP);
                if (!child) { snprintf(msg, n, "invalid name '%s'", c[i].text); return -1; }
                if (!hooked && hooktext) { set_hook(child, hooktext); hooked = 1; }
            }
            cur = child;
        } else {
            if (ctype != SF_KEY_LIST) {
                if (ctype == SF_KEY_VEC2 || ctype == SF_KEY_VEC3 || ctype == SF_KEY_BOOL3 || ctype == SF_KEY_NAMES)
                    snprintf(msg, n, "%s is an array: set it whole (e.g. %s=%s)", shown, shown, key_type_name(ctype));
                else
                    snprintf(msg, n, "%s is not a list", shown[0] ? shown : "the study");
                return -1;
            }
            join3(npat, sizeof npat, pat, "[]", "");
            ck = schema_find(npat);
            if (!ck) { snprintf(msg, n, "'%s' is not in the schema", npat); return -1; }
            config_setting_t *child = NULL;
            if (cur && cur->type != CONFIG_TYPE_LIST && cur->type != CONFIG_TYPE_ARRAY) {
                snprintf(msg, n, "%s is not a list", shown);
                return -1;
            }
            int len = cur ? config_setting_length(cur) : 0;
            if (c[i].kind == COMP_INDEX) {
                if (c[i].index >= len) {
                    if (len == 0) snprintf(msg, n, "%s has no elements", shown);
                    else snprintf(msg, n, "%s has %d element%s (index 0 to %d)", shown, len, len == 1 ? "" : "s", len - 1);
                    return -1;
                }
                child = config_setting_get_elem(cur, (unsigned)c[i].index);
            } else {
                const char *names[256];
                int nn = 0;
                for (int j = 0; j < len; j++) {
                    config_setting_t *e = config_setting_get_elem(cur, (unsigned)j);
                    config_setting_t *nm = mem(e, "name");
                    const char *t = nm && nm->type == CONFIG_TYPE_STRING ? nm->value.sval : NULL;
                    if (t && strcmp(t, c[i].text) == 0) { child = e; break; }
                    if (t && nn < 256) names[nn++] = t;
                }
                if (!child) {
                    char h[600];
                    snprintf(msg, n, "no element named '%s' in %s%s", c[i].text, shown,
                             hint(h, sizeof h, sf_study_suggest(c[i].text, nn, names)));
                    return -1;
                }
            }
            join3(pat, sizeof pat, npat, "", "");
            size_t ls = strlen(shown);
            snprintf(shown + ls, sizeof shown - ls, "[%s]", c[i].text);
            if (last) {
                r->parent = cur;
                r->node = child;
                r->name[0] = '\0';
                break;
            }
            cur = child;
        }
    }
    r->key = ck;
    join3(r->pattern, sizeof r->pattern, pat, "", "");
    return 0;
}

/* ---------------------------------------------------------------------- */
/* --set overrides                                                         */
/* ---------------------------------------------------------------------- */

static void trim(char *t)
{
    size_t n = strlen(t);
    while (n && isspace((unsigned char)t[n - 1])) t[--n] = '\0';
    size_t i = 0;
    while (isspace((unsigned char)t[i])) i++;
    if (i) memmove(t, t + i, n - i + 1);
}

static int apply_set(config_t *cfg, const char *text, sf_error *err)
{
    char key[512], val[4096], shown[4700], msg[1024];
    const char *eq = strchr(text, '=');
    if (!eq)
        return sf_fail(err, SF_EINPUT, "--set %s: expected key=value", text);
    size_t lk = (size_t)(eq - text);
    if (lk >= sizeof key || strlen(eq + 1) >= sizeof val)
        return sf_fail(err, SF_EINPUT, "--set %.60s...: too long", text);
    memcpy(key, text, lk);
    key[lk] = '\0';
    snprintf(val, sizeof val, "%s", eq + 1);
    trim(key);
    trim(val);
    size_t lv = strlen(val);
    if (lv && val[lv - 1] == ';') { val[--lv] = '\0'; trim(val); }
    snprintf(shown, sizeof shown, "--set %s=%s", key, val);
    for (char *p = shown; *p; p++) if (*p == '\n' || *p == '\r') *p = ' ';
    if (!key[0]) return sf_fail(err, SF_EINPUT, "%s: empty key", shown);
    if (!val[0]) return sf_fail(err, SF_EINPUT, "%s: empty value", shown);

    char tok[64];
    if (find_int_overflow(val, tok, sizeof tok))
        return sf_fail(err, SF_EINPUT,
                       "%s: integer %s is out of range (libconfig would wrap it): write it with a decimal point",
                       shown, tok);

    /* parse the value */
    size_t lb = lv + 16;
    char *buf = malloc(lb);
    if (!buf) return sf_fail(err, SF_ENOMEM, "out of memory");
    snprintf(buf, lb, "v = %s;\n", val);
    config_t tmp;
    config_init(&tmp);
    int ok = config_read_string(&tmp, buf);
    free(buf);
    if (!ok) {
        int r = sf_fail(err, SF_EINPUT, "%s: %s (the value must be in libconfig syntax, e.g. 0.02, \"text\", [0.0, 1.0], true)",
                        shown, config_error_text(&tmp));
        config_destroy(&tmp);
        return r;
    }
    config_setting_t *root = config_root_setting(&tmp);
    config_setting_t *v = config_setting_get_member(root, "v");
    if (config_setting_length(root) != 1 || !v) {
        config_destroy(&tmp);
        return sf_fail(err, SF_EINPUT, "%s: the value must be a single value", shown);
    }

    resolved r;
    if (resolve(cfg, key, 1, shown, &r, msg, sizeof msg)) {
        config_destroy(&tmp);
        return sf_fail(err, SF_EINPUT, "%s: %s", shown, msg);
    }
    config_setting_t *t = r.node;
    int rc = SF_OK;
    if (t && t->type == CONFIG_TYPE_FLOAT && (v->type == CONFIG_TYPE_INT || v->type == CONFIG_TYPE_INT64)) {
        /* an integer for a real number: keep the setting (and its place) */
        if (!config_setting_set_float(t, numval(v)))
            rc = sf_fail(err, SF_EINTERNAL, "%s: cannot copy the value", shown);
    } else if (t && t->type == v->type) {
        if (config_setting_is_aggregate(t))
            while (config_setting_length(t) > 0) config_setting_remove_elem(t, 0);
        if (copy_value(t, v)) rc = sf_fail(err, SF_EINTERNAL, "%s: cannot copy the value", shown);
    } else if (t && (!r.name[0] || !r.parent || r.parent->type != CONFIG_TYPE_GROUP)) {
        rc = sf_fail(err, SF_EINPUT, "%s: expected %s, got %s", shown,
                     r.key ? key_type_name(r.key->type) : type_name(t->type), type_name(v->type));
    } else {
        if (!r.parent || r.parent->type != CONFIG_TYPE_GROUP) {
            config_destroy(&tmp);
            return sf_fail(err, SF_EINPUT, "%s: cannot set a key inside something that is not a group", shown);
        }
        if (t) config_setting_remove(r.parent, r.name);
        t = config_setting_add(r.parent, r.name, v->type);
        if (!t) rc = sf_fail(err, SF_EINPUT, "%s: invalid name '%s'", shown, r.name);
        else if (copy_value(t, v)) rc = sf_fail(err, SF_EINTERNAL, "%s: cannot copy the value", shown);
    }
    if (rc == SF_OK) set_hook(t, shown);
    config_destroy(&tmp);
    return rc;
}

/* ---------------------------------------------------------------------- */
/* Generic check against the schema                                        */
/* ---------------------------------------------------------------------- */

static int check_bounds(const sf_study *s, sf_error *err,
                        const config_setting_t *st, const sf_study_key *k,
                        double x)
{
    char got[64];
    unsigned f = k->flags;
    show(st, got, sizeof got);
    int isint = k->type == SF_KEY_INT;
    if (!isfinite(x))
        return bad(s, err, st, "must be a finite number (got %s)", got);
    int ok = 1;
    if ((f & SF_KEY_GT) && !(x > k->lo)) ok = 0;
    if ((f & SF_KEY_GE) && !(x >= k->lo)) ok = 0;
    if ((f & SF_KEY_LT) && !(x < k->hi)) ok = 0;
    if ((f & SF_KEY_LE) && !(x <= k->hi)) ok = 0;
    if (ok) return SF_OK;
    unsigned lower = f & (SF_KEY_GT | SF_KEY_GE), upper = f & (SF_KEY_LT | SF_KEY_LE);
    if (!upper && lower == SF_KEY_GT && k->lo == 0)
        return bad(s, err, st, "must be positive (got %s)", got);
    if (!upper && lower == SF_KEY_GE && k->lo == 0)
        return bad(s, err, st, "must not be negative (got %s)", got);
    if (!upper && lower == SF_KEY_GE)
        return bad(s, err, st, "must be at least %g (got %s)", k->lo, got);
    if (!upper && lower == SF_KEY_GT)
        return bad(s, err, st, "must be greater than %g (got %s)", k->lo, got);
    if (isint && lower == SF_KEY_GE && upper == SF_KEY_LE && k->hi - k->lo == 1)
        return bad(s, err, st, "must be %g or %g (got %s)", k->lo, k->hi, got);
    if (lower == SF_KEY_GE && upper == SF_KEY_LE)
        return bad(s, err, st, "must be between %g and %g (got %s)", k->lo, k->hi, got);
    return bad(s, err, st, "must be in %s%g, %g%s (got %s)",
               lower == SF_KEY_GT ? "(" : "[", k->lo, k->hi,
               upper == SF_KEY_LT ? ")" : "]", got);
}

static int check_node(const sf_study *s, sf_error *err,
                      const config_setting_t *st, const sf_study_key *k,
                      const char *pat);

static int check_group(const sf_study *s, sf_error *err,
                       const config_setting_t *st, const char *pat)
{
    int n = config_setting_length(st);
    char kp[512];
    keypath(st, kp, sizeof kp);
    for (int i = 0; i < n; i++) {
        const config_setting_t *m = config_setting_get_elem(st, (unsigned)i);
        char cp[512];
        join3(cp, sizeof cp, pat, pat[0] ? "." : "", m->name);
        const sf_study_key *ck = schema_find(cp);
        if (!ck) {
            char sb[512], h[600];
            const char *sg = suggest_key(pat, m->name, sb, sizeof sb);
            if (kp[0])
                return bad_raw(s, err, m, "unknown key '%s' in %s%s", m->name, kp, hint(h, sizeof h, sg));
            return bad_raw(s, err, m, "unknown key '%s' at top level%s", m->name, hint(h, sizeof h, sg));
        }
        int rc = check_node(s, err, m, ck, cp);
        if (rc) return rc;
    }
    for (int i = 0; i < NSCHEMA; i++) {
        const char *name;
        if (!(schema[i].flags & SF_KEY_REQUIRED)) continue;
        if (!schema_is_child(&schema[i], pat, &name)) continue;
        if (strcmp(name, "*") == 0 || strcmp(name, "[]") == 0) continue;
        if (!config_setting_get_member(st, name)) {
            if (kp[0]) return bad(s, err, st, "missing required key '%s'", name);
            return bad_raw(s, err, st, "missing required key '%s'", name);
        }
    }
    return SF_OK;
}

static int check_node(const sf_study *s, sf_error *err,
                      const config_setting_t *st, const sf_study_key *k,
                      const char *pat)
{
    char got[128], cp[512];
    int t = st->type;
    switch (k->type) {
    case SF_KEY_GROUP:
        if (t != CONFIG_TYPE_GROUP)
            return bad(s, err, st, "expected a group { ... }, got %s", show(st, got, sizeof got));
        return check_group(s, err, st, pat);
    case SF_KEY_NAMED: {
        if (t != CONFIG_TYPE_GROUP)
            return bad(s, err, st, "expected a group { name = ...; ... }, got %s", show(st, got, sizeof got));
        join3(cp, sizeof cp, pat, ".*", "");
        const sf_study_key *ck = schema_find(cp);
        int n = config_setting_length(st);
        for (int i = 0; i < n && ck; i++) {
            const config_setting_t *m = config_setting_get_elem(st, (unsigned)i);
            if (strlen(m->name) >= SF_NAME_MAX)
                return bad_raw(s, err, m, "name '%.20s...' is too long (at most %d characters)", m->name, SF_NAME_MAX - 1);
            int rc = check_node(s, err, m, ck, cp);
            if (rc) return rc;
        }
        return SF_OK;
    }
    case SF_KEY_LIST: {
        int n = config_setting_length(st);
        if (t == CONFIG_TYPE_ARRAY && n == 0) return SF_OK;  /* [] is an empty list too */
        if (t != CONFIG_TYPE_LIST)
            return bad(s, err, st, "expected a list ( {...}, {...} ), got %s", show(st, got, sizeof got));
        join3(cp, sizeof cp, pat, "[]", "");
        const sf_study_key *ck = schema_find(cp);
        for (int i = 0; i < n && ck; i++) {
            int rc = check_node(s, err, config_setting_get_elem(st, (unsigned)i), ck, cp);
            if (rc) return rc;
        }
        return SF_OK;
    }
    case SF_KEY_NUMBER:
        if (!is_num(st))
            return bad(s, err, st, "expected a number, got %s", show(st, got, sizeof got));
        return check_bounds(s, err, st, k, numval(st));
    case SF_KEY_INT:
        if (t == CONFIG_TYPE_FLOAT)
            return bad(s, err, st, "expected an integer, got %s", show(st, got, sizeof got));
        if (t != CONFIG_TYPE_INT && t != CONFIG_TYPE_INT64)
            return bad(s, err, st, "expected an integer, got %s", show(st, got, sizeof got));
        if (t == CONFIG_TYPE_INT64 && (st->value.llval > INT_MAX || st->value.llval < INT_MIN))
            return bad(s, err, st, "integer out of range (got %lld)", st->value.llval);
        return check_bounds(s, err, st, k, numval(st));
    case SF_KEY_STRING: {
        if (t != CONFIG_TYPE_STRING)
            return bad(s, err, st, "expected a string \"...\", got %s", show(st, got, sizeof got));
        const char *v = st->value.sval ? st->value.sval : "";
        if (k->choices) {
            char buf[256];
            snprintf(buf, sizeof buf, "%s", k->choices);
            const char *cand[16];
            int nc = 0, found = 0;
            char *save = NULL;
            for (char *tk = strtok_r(buf, "|", &save); tk && nc < 16; tk = strtok_r(NULL, "|", &save)) {
                cand[nc++] = tk;
                if (strcmp(tk, v) == 0) found = 1;
            }
            if (!found) {
                char list[300] = "";
                for (int i = 0; i < nc; i++) {
                    size_t l = strlen(list);
                    snprintf(list + l, sizeof list - l, "%s\"%s\"", i ? (i == nc - 1 ? " or " : ", ") : "", cand[i]);
                }
                char h[300];
                return bad(s, err, st, "must be %s (got \"%s\")%s", list, v,
                           hint(h, sizeof h, sf_study_suggest(v, nc, cand)));
            }
        }
        if ((k->flags & (SF_KEY_IDENT | SF_KEY_FILESAFE)) && strlen(v) >= SF_NAME_MAX)
            return bad(s, err, st, "too long (at most %d characters)", SF_NAME_MAX - 1);
        if ((k->flags & SF_KEY_IDENT) && !is_ident(v))
            return bad(s, err, st, "'%s' is not a valid name (letters, digits, '_' and '-', starting with a letter or '_')", v);
        if ((k->flags & SF_KEY_FILESAFE) && !is_filesafe(v))
            return bad(s, err, st, "'%s' is not a valid name (use letters, digits, '_', '-' and '.')", v);
        return SF_OK;
    }
    case SF_KEY_BOOL:
        if (t != CONFIG_TYPE_BOOL)
            return bad(s, err, st, "expected true or false, got %s", show(st, got, sizeof got));
        return SF_OK;
    case SF_KEY_VEC2:
    case SF_KEY_VEC3:
    case SF_KEY_BOOL3: {
        int want = k->type == SF_KEY_VEC2 ? 2 : 3;
        int isb = k->type == SF_KEY_BOOL3;
        if (t != CONFIG_TYPE_ARRAY && t != CONFIG_TYPE_LIST)
            return bad(s, err, st, "expected %s, got %s", key_type_name(k->type), show(st, got, sizeof got));
        int n = config_setting_length(st);
        if (n != want)
            return bad(s, err, st, "expected %s (%d %s), got %d element%s", key_type_name(k->type),
                       want, isb ? "booleans" : "numbers", n, n == 1 ? "" : "s");
        for (int i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(st, (unsigned)i);
            if (isb) {
                if (e->type != CONFIG_TYPE_BOOL)
                    return bad(s, err, e, "expected true or false, got %s", show(e, got, sizeof got));
            } else {
                if (!is_num(e))
                    return bad(s, err, e, "expected a number, got %s", show(e, got, sizeof got));
                int rc = check_bounds(s, err, e, k, numval(e));
                if (rc) return rc;
            }
        }
        return SF_OK;
    }
    case SF_KEY_NAMES: {
        if (t != CONFIG_TYPE_ARRAY && t != CONFIG_TYPE_LIST)
            return bad(s, err, st, "expected %s, got %s", key_type_name(k->type), show(st, got, sizeof got));
        int n = config_setting_length(st);
        for (int i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(st, (unsigned)i);
            if (e->type != CONFIG_TYPE_STRING)
                return bad(s, err, e, "expected a name \"...\", got %s", show(e, got, sizeof got));
        }
        return SF_OK;
    }
    default:
        return sf_fail(err, SF_EINTERNAL, "study schema: bad type for %s", k->path);
    }
}

/* ---------------------------------------------------------------------- */
/* Semantic checks and filling sf_study                                    */
/* ---------------------------------------------------------------------- */

/* Numbers of a default text "[0.0, 1.0]" / "24" / "true". */
static int parse_def(const char *def, double *out, int max)
{
    int n = 0;
    const char *p = def;
    while (*p && n < max) {
        while (*p && (*p == '[' || *p == ']' || *p == ',' || isspace((unsigned char)*p))) p++;
        if (!*p) break;
        if (strncmp(p, "true", 4) == 0) { out[n++] = 1; p += 4; continue; }
        if (strncmp(p, "false", 5) == 0) { out[n++] = 0; p += 5; continue; }
        char *e;
        double v = strtod(p, &e);
        if (e == p) break;
        out[n++] = v;
        p = e;
    }
    return n;
}

static double def_num(const char *pattern)
{
    const sf_study_key *k = schema_find(pattern);
    double v = 0;
    if (k && k->def) parse_def(k->def, &v, 1);
    return v;
}

/* Value of key in g, or of the same key in dflt (a group of defaults),
 * else the schema default of dpattern.  which (if non-NULL) receives the
 * setting used (NULL for a schema default). */
static double get_num(const config_setting_t *g, const config_setting_t *dflt,
                      const char *key, const char *dpattern,
                      const config_setting_t **which)
{
    const config_setting_t *m = mem(g, key);
    if (!m) m = mem(dflt, key);
    if (which) *which = m;
    if (m) return numval(m);
    return def_num(dpattern);
}

static void get_vec(const config_setting_t *g, const config_setting_t *dflt,
                    const char *key, const char *dpattern, double *out,
                    int n)
{
    const config_setting_t *m = mem(g, key);
    if (!m) m = mem(dflt, key);
    for (int i = 0; i < n; i++) out[i] = 0;
    if (m) {
        for (int i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(m, (unsigned)i);
            out[i] = e->type == CONFIG_TYPE_BOOL ? (double)e->value.ival : numval(e);
        }
    } else {
        const sf_study_key *k = schema_find(dpattern);
        if (k && k->def) parse_def(k->def, out, n);
    }
}

static const char *get_str(const config_setting_t *g, const char *key,
                           const char *dpattern)
{
    const config_setting_t *m = mem(g, key);
    if (m) return m->value.sval;
    const sf_study_key *k = schema_find(dpattern);
    return k && k->def ? k->def : NULL;
}

static int get_bool(const config_setting_t *g, const char *key,
                    const char *dpattern)
{
    const config_setting_t *m = mem(g, key);
    if (m) return m->value.ival;
    return def_num(dpattern) != 0;
}

static int find_name(const char *name, const void *base, size_t stride, int n)
{
    for (int i = 0; i < n; i++) {
        const char *nm = (const char *)base + (size_t)i * stride;
        if (strcmp(nm, name) == 0) return i;
    }
    return -1;
}

/* Suggestion among n names laid out with stride. */
static const char *suggest_in(const char *word, const void *base,
                              size_t stride, int n)
{
    const char **cand = malloc((size_t)(n > 0 ? n : 1) * sizeof *cand);
    if (!cand) return NULL;
    for (int i = 0; i < n; i++) cand[i] = (const char *)base + (size_t)i * stride;
    const char *r = sf_study_suggest(word, n, cand);
    free(cand);
    return r;
}

static int fill(sf_study *s, config_t *cfg, sf_error *err)
{
    const config_setting_t *root = config_root_setting(cfg);
    char h[200];

    copy_name(s->name, mem(root, "name")->value.sval);

    /* vertices */
    const config_setting_t *vs = mem(root, "vertices");
    int nv = config_setting_length(vs);
    if (nv == 0) return bad(s, err, vs, "no vertices");
    s->vertices = calloc((size_t)nv, sizeof *s->vertices);
    if (!s->vertices) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->nvertices = nv;
    for (int i = 0; i < nv; i++) {
        const config_setting_t *e = config_setting_get_elem(vs, (unsigned)i);
        copy_name(s->vertices[i].name, e->name);
        s->vertices[i].x[0] = numval(config_setting_get_elem(e, 0));
        s->vertices[i].x[1] = numval(config_setting_get_elem(e, 1));
        s->vertices[i].line = (int)e->line;
    }
#define VIDX(nm) find_name((nm), s->vertices[0].name, sizeof(sf_vertex), s->nvertices)
#define VSUG(nm) suggest_in((nm), s->vertices[0].name, sizeof(sf_vertex), s->nvertices)

    /* outline */
    const config_setting_t *ol = mem(mem(root, "sheet"), "outline");
    int no = config_setting_length(ol);
    if (no < 3) return bad(s, err, ol, "needs at least 3 vertices (got %d)", no);
    s->outline = calloc((size_t)no, sizeof *s->outline);
    if (!s->outline) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->noutline = no;
    for (int i = 0; i < no; i++) {
        const config_setting_t *e = config_setting_get_elem(ol, (unsigned)i);
        int k = VIDX(e->value.sval);
        if (k < 0)
            return bad(s, err, e, "unknown vertex '%s'%s", e->value.sval, hint(h, sizeof h, VSUG(e->value.sval)));
        for (int j = 0; j < i; j++)
            if (s->outline[j] == k)
                return bad(s, err, e, "vertex '%s' appears twice in the outline", e->value.sval);
        s->outline[i] = k;
    }

    /* materials */
    const config_setting_t *ms = mem(root, "materials");
    int nm = config_setting_length(ms);
    if (nm == 0) return bad(s, err, ms, "no materials");
    s->materials = calloc((size_t)nm, sizeof *s->materials);
    if (!s->materials) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->nmaterials = nm;
    for (int i = 0; i < nm; i++) {
        const config_setting_t *e = config_setting_get_elem(ms, (unsigned)i);
        sf_material *m = &s->materials[i];
        copy_name(m->name, e->name);
        m->E = mem(e, "E") ? numval(mem(e, "E")) : 0.0;
        m->nu = mem(e, "nu") ? numval(mem(e, "nu")) : 0.0;
        m->thickness = numval(mem(e, "thickness"));
        m->density = mem(e, "density") ? numval(mem(e, "density")) : 0.0;
    }
#define MIDX(nm) find_name((nm), s->materials[0].name, sizeof(sf_material), s->nmaterials)
#define MSUG(nm) suggest_in((nm), s->materials[0].name, sizeof(sf_material), s->nmaterials)

    /* faces */
    s->face_material = -1;
    const config_setting_t *fm = mem(mem(root, "faces"), "material");
    if (fm) {
        s->face_material = MIDX(fm->value.sval);
        if (s->face_material < 0)
            return bad(s, err, fm, "unknown material '%s'%s", fm->value.sval, hint(h, sizeof h, MSUG(fm->value.sval)));
    }

    /* actuation groups */
    const config_setting_t *as = mem(root, "actuation");
    int ng = as ? config_setting_length(as) : 0;
    if (ng) {
        s->groups = calloc((size_t)ng, sizeof *s->groups);
        if (!s->groups) return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int i = 0; i < ng; i++) {
        const config_setting_t *e = config_setting_get_elem(as, (unsigned)i);
        const config_setting_t *n = mem(e, "name");
        if (find_name(n->value.sval, s->groups[0].name, sizeof(sf_group), i) >= 0)
            return bad(s, err, n, "group '%s' is defined twice", n->value.sval);
        copy_name(s->groups[i].name, n->value.sval);
        s->groups[i].rest_angle = numval(mem(e, "rest_angle"));
        s->groups[i].line = (int)e->line;
        s->ngroups = i + 1;
    }

    /* folds */
    const config_setting_t *dft = mem(root, "defaults");
    const config_setting_t *fs = mem(root, "folds");
    int nf = config_setting_length(fs);
    if (nf == 0) return bad(s, err, fs, "no folds");
    s->folds = calloc((size_t)nf, sizeof *s->folds);
    if (!s->folds) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->nfolds = nf;
    for (int i = 0; i < nf; i++) {
        const config_setting_t *e = config_setting_get_elem(fs, (unsigned)i);
        sf_fold_def *f = &s->folds[i];
        f->line = (int)e->line;
        const config_setting_t *from = mem(e, "from"), *to = mem(e, "to");
        f->a = VIDX(from->value.sval);
        if (f->a < 0)
            return bad(s, err, from, "unknown vertex '%s'%s", from->value.sval, hint(h, sizeof h, VSUG(from->value.sval)));
        f->b = VIDX(to->value.sval);
        if (f->b < 0)
            return bad(s, err, to, "unknown vertex '%s'%s", to->value.sval, hint(h, sizeof h, VSUG(to->value.sval)));
        if (f->a == f->b)
            return bad2(s, err, to->hook ? to : from->hook ? from : e, e,
                        "from and to are the same vertex '%s'", from->value.sval);
        const config_setting_t *nmset = mem(e, "name");
        if (nmset) {
            if (find_name(nmset->value.sval, s->folds[0].name, sizeof(sf_fold_def), i) >= 0)
                return bad(s, err, nmset, "fold name '%s' is used twice", nmset->value.sval);
            copy_name(f->name, nmset->value.sval);
        }
        const config_setting_t *wset;
        f->width = get_num(e, dft, "width", "defaults.width", &wset);
        if (!wset)
            return bad(s, err, e, "no width (give width here or defaults.width)");
        get_vec(e, dft, "setback", "defaults.setback", f->setback, 2);
        f->continuity = (int)get_num(e, dft, "continuity", "defaults.continuity", NULL);
        f->modes = (int)get_num(e, dft, "modes", "defaults.modes", NULL);
        f->rest_angle = get_num(e, dft, "rest_angle", "defaults.rest_angle", NULL);
        /* material */
        const config_setting_t *mset = mem(e, "material");
        if (!mset) mset = mem(dft, "material");
        const char *mname = mset ? mset->value.sval : "fold";
        f->material = MIDX(mname);
        if (f->material < 0) {
            if (mset)
                return bad(s, err, mset, "unknown material '%s'%s", mname, hint(h, sizeof h, MSUG(mname)));
            return bad(s, err, e, "no material given and no material named 'fold' (set defaults.material or material here)");
        }
        const config_setting_t *mse = mem(ms, mname);
        if (!mem(mse, "E"))
            return bad(s, err, mse, "missing E (required because folds[%d] uses this material)", i);
        if (!mem(mse, "nu"))
            return bad(s, err, mse, "missing nu (required because folds[%d] uses this material)", i);
        /* group */
        f->group = -1;
        const config_setting_t *gset = mem(e, "group");
        if (gset) {
            f->group = find_name(gset->value.sval, s->groups ? s->groups[0].name : "", sizeof(sf_group), s->ngroups);
            if (f->group < 0) {
                const char *sg = s->ngroups ? suggest_in(gset->value.sval, s->groups[0].name, sizeof(sf_group), s->ngroups) : NULL;
                return bad(s, err, gset, "unknown group '%s'%s%s", gset->value.sval, hint(h, sizeof h, sg),
                           s->ngroups ? "" : " (no actuation groups are defined)");
            }
        }
    }

    /* loads and stages */
    const config_setting_t *ls = mem(root, "loads");
    int nl = ls ? config_setting_length(ls) : 0;
    if (nl) {
        s->loads = calloc((size_t)nl, sizeof *s->loads);
        if (!s->loads) return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    s->nloads = nl;
    int maxstage = 1;
    for (int i = 0; i < nl; i++) {
        const config_setting_t *e = config_setting_get_elem(ls, (unsigned)i);
        sf_point_load *L = &s->loads[i];
        get_vec(e, NULL, "at", "", L->at, 2);
        get_vec(e, NULL, "force", "", L->force, 3);
        L->stage = (int)get_num(e, NULL, "stage", "loads[].stage", NULL);
        L->line = (int)e->line;
        if (L->stage > maxstage) maxstage = L->stage;
    }
    const config_setting_t *gr = mem(root, "gravity");
    if (gr && get_bool(gr, "enabled", "gravity.enabled")) {
        s->gravity_on = 1;
        get_vec(gr, NULL, "g", "", s->gravity, 3);
        s->gravity_stage = (int)get_num(gr, NULL, "stage", "gravity.stage", NULL);
        if (s->gravity_stage > maxstage) maxstage = s->gravity_stage;
    } else {
        s->gravity_stage = 1;
    }
    s->nstages = maxstage;
    for (int k = 1; k < maxstage; k++) {
        int used = s->gravity_on && s->gravity_stage == k;
        for (int i = 0; i < nl; i++) used |= s->loads[i].stage == k;
        if (used) continue;
        /* blame the first thing in a later stage */
        const config_setting_t *blame = NULL;
        for (int i = 0; i < nl && !blame; i++)
            if (s->loads[i].stage > k)
                blame = mem(config_setting_get_elem(ls, (unsigned)i), "stage");
        if (!blame) blame = mem(gr, "stage");
        return bad(s, err, blame, "stage %d has no loads (stages must be 1, 2, ... without gaps)", k);
    }

    /* supports */
    const config_setting_t *sp = mem(root, "supports");
    int ns = sp ? config_setting_length(sp) : 0;
    if (ns) {
        s->supports = calloc((size_t)ns, sizeof *s->supports);
        if (!s->supports) return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    s->nsupports = ns;
    for (int i = 0; i < ns; i++) {
        const config_setting_t *e = config_setting_get_elem(sp, (unsigned)i);
        sf_support *S = &s->supports[i];
        double fix[3];
        get_vec(e, NULL, "at", "", S->at, 2);
        get_vec(e, NULL, "fix", "supports[].fix", fix, 3);
        get_vec(e, NULL, "value", "supports[].value", S->value, 3);
        for (int d = 0; d < 3; d++) S->dof[d] = fix[d] != 0;
        S->line = (int)e->line;
        if (!S->dof[0] && !S->dof[1] && !S->dof[2])
            return bad(s, err, mem(e, "fix"), "fixes nothing (at least one component must be true)");
    }

    /* probes */
    const config_setting_t *ps = mem(root, "probes");
    int np = ps ? config_setting_length(ps) : 0;
    if (np) {
        s->probes = calloc((size_t)np, sizeof *s->probes);
        if (!s->probes) return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int i = 0; i < np; i++) {
        const config_setting_t *e = config_setting_get_elem(ps, (unsigned)i);
        const config_setting_t *n = mem(e, "name");
        if (find_name(n->value.sval, s->probes[0].name, sizeof(sf_probe), i) >= 0)
            return bad(s, err, n, "probe name '%s' is used twice", n->value.sval);
        copy_name(s->probes[i].name, n->value.sval);
        get_vec(e, NULL, "at", "", s->probes[i].at, 2);
        s->probes[i].line = (int)e->line;
        s->nprobes = i + 1;
    }

    /* fixed face */
    const config_setting_t *ff = mem(root, "fixed_face");
    get_vec(root, NULL, "fixed_face", "", s->fixed_point, 2);
    s->fixed_line = (int)ff->line;

    /* solver, output */
    const config_setting_t *so = mem(root, "solver");
    const char *cons = get_str(so, "constraints", "solver.constraints");
    s->constraints = strcmp(cons, "penalty") == 0 ? SF_CONSTRAINTS_PENALTY : SF_CONSTRAINTS_EXACT;
    s->penalty_rotation = get_num(so, NULL, "penalty_rotation", "solver.penalty_rotation", NULL);
    s->penalty_translation = get_num(so, NULL, "penalty_translation", "solver.penalty_translation", NULL);
    s->quadrature = (int)get_num(so, NULL, "quadrature", "solver.quadrature", NULL);
    s->tolerance = get_num(so, NULL, "tolerance", "solver.tolerance", NULL);
    const config_setting_t *ou = mem(root, "output");
    s->samples = (int)get_num(ou, NULL, "samples", "output.samples", NULL);
    s->shapes = (int)get_num(ou, NULL, "shapes", "output.shapes", NULL);

    /* analysis */
    const config_setting_t *an = mem(root, "analysis");
    const char *type = get_str(an, "type", "analysis.type");
    copy_name(s->analysis_type, type);
    int dynamics = strcmp(type, "dynamics") == 0;
    const char *param = get_str(an, "parameter", "analysis.parameter");
    const config_setting_t *agr = mem(an, "group");
    if (agr && agr->value.sval[0]) {
        if (find_name(agr->value.sval, s->groups ? s->groups[0].name : "", sizeof(sf_group), s->ngroups) < 0) {
            const char *sg = s->ngroups ? suggest_in(agr->value.sval, s->groups[0].name, sizeof(sf_group), s->ngroups) : NULL;
            return bad(s, err, agr, "unknown group '%s'%s%s", agr->value.sval, hint(h, sizeof h, sg),
                       s->ngroups ? "" : " (no actuation groups are defined)");
        }
    }
    if (strcmp(param, "actuation") == 0 && s->ngroups == 0)
        return bad(s, err, mem(an, "parameter"), "\"actuation\" needs at least one actuation group");
    const config_setting_t *rep = mem(an, "report");
    if (rep && rep->value.sval[0]
        && find_name(rep->value.sval, s->probes ? s->probes[0].name : "", sizeof(sf_probe), s->nprobes) < 0) {
        const char *sg = s->nprobes ? suggest_in(rep->value.sval, s->probes[0].name, sizeof(sf_probe), s->nprobes) : NULL;
        return bad(s, err, rep, "unknown probe '%s'%s%s", rep->value.sval, hint(h, sizeof h, sg),
                   s->nprobes ? "" : " (no probes are defined)");
    }
    {
        const config_setting_t *w1, *w2, *w3;
        double st = get_num(an, NULL, "step", "analysis.step", &w1);
        double mn = get_num(an, NULL, "min_step", "analysis.min_step", &w2);
        double mx = get_num(an, NULL, "max_step", "analysis.max_step", &w3);
        if (mn > mx)
            return bad(s, err, w2 ? w2 : w3 ? w3 : an, "min_step %g is larger than max_step %g", mn, mx);
        if (st < mn || st > mx)
            return bad(s, err, w1 ? w1 : an, "step %g is outside [min_step, max_step] = [%g, %g]", st, mn, mx);
    }
    if (dynamics) {
        if (!mem(an, "duration"))
            return bad(s, err, an, "missing duration (required when type is \"dynamics\")");
        const config_setting_t *sc = mem(an, "schedule");
        int nsc = sc ? config_setting_length(sc) : 0;
        double tprev = -INFINITY;
        for (int i = 0; i < nsc; i++) {
            const config_setting_t *e = config_setting_get_elem(sc, (unsigned)i);
            double t = numval(mem(e, "t"));
            if (!(t > tprev))
                return bad(s, err, mem(e, "t"), "times must increase (got %g after %g)", t, tprev);
            tprev = t;
        }
        /* the other time histories of a trajectory: same rule */
        const config_setting_t *lists[64];
        int nl = 0;
        lists[nl++] = mem(an, "load_schedule");
        const config_setting_t *acts = mem(root, "actuation");
        for (int g = 0; acts && g < config_setting_length(acts) && nl < 64; g++)
            lists[nl++] = mem(config_setting_get_elem(acts, (unsigned)g), "schedule");
        for (int l = 0; l < nl; l++) {
            int nlen = lists[l] ? config_setting_length(lists[l]) : 0;
            tprev = -INFINITY;
            for (int i = 0; i < nlen; i++) {
                const config_setting_t *e = config_setting_get_elem(lists[l], (unsigned)i);
                double t = numval(mem(e, "t"));
                if (!(t > tprev))
                    return bad(s, err, mem(e, "t"), "times must increase (got %g after %g)", t, tprev);
                tprev = t;
            }
        }
    }

    /* densities where mass matters */
    int inertia = dynamics && get_bool(an, "inertia", "analysis.inertia");
    if (s->gravity_on && s->face_material < 0)
        return bad(s, err, gr, "needs faces.material (the weight of the faces comes from its thickness and density)");
    if (s->gravity_on || inertia) {
        for (int i = -1; i < s->nfolds; i++) {
            int mi = i < 0 ? s->face_material : s->folds[i].material;
            if (mi < 0) continue;
            const config_setting_t *mse = mem(ms, s->materials[mi].name);
            if (!mem(mse, "density"))
                return bad(s, err, mse, "missing density (required when %s is on)", s->gravity_on ? "gravity" : "inertia");
        }
    }
    return SF_OK;
#undef VIDX
#undef VSUG
#undef MIDX
#undef MSUG
}

/* ---------------------------------------------------------------------- */
/* Defaults into the tree (so the written study and accessors see them)    */
/* ---------------------------------------------------------------------- */

static int put_default(config_setting_t *g, const char *name,
                       const sf_study_key *k)
{
    double v[3];
    config_setting_t *m;
    switch (k->type) {
    case SF_KEY_NUMBER:
        parse_def(k->def, v, 1);
        m = config_setting_add(g, name, CONFIG_TYPE_FLOAT);
        return m && config_setting_set_float(m, v[0]) ? 0 : -1;
    case SF_KEY_INT:
        parse_def(k->def, v, 1);
        m = config_setting_add(g, name, CONFIG_TYPE_INT);
        return m && config_setting_set_int(m, (int)v[0]) ? 0 : -1;
    case SF_KEY_BOOL:
        parse_def(k->def, v, 1);
        m = config_setting_add(g, name, CONFIG_TYPE_BOOL);
        return m && config_setting_set_bool(m, v[0] != 0) ? 0 : -1;
    case SF_KEY_STRING:
        m = config_setting_add(g, name, CONFIG_TYPE_STRING);
        return m && config_setting_set_string(m, k->def) ? 0 : -1;
    case SF_KEY_VEC2:
    case SF_KEY_VEC3:
    case SF_KEY_BOOL3: {
        int n = k->type == SF_KEY_VEC2 ? 2 : 3;
        parse_def(k->def, v, n);
        m = config_setting_add(g, name, CONFIG_TYPE_ARRAY);
        if (!m) return -1;
        for (int i = 0; i < n; i++) {
            if (k->type == SF_KEY_BOOL3) {
                if (!config_setting_set_bool_elem(m, -1, v[i] != 0)) return -1;
            } else if (!config_setting_set_float_elem(m, -1, v[i])) {
                return -1;
            }
        }
        return 0;
    }
    default:
        return -1;
    }
}

static int materialize(sf_study *s, config_t *cfg, sf_error *err)
{
    config_setting_t *root = config_root_setting(cfg);
    config_setting_t *an = mem(root, "analysis");
    const char *type = get_str(an, "type", "analysis.type");
    int dynamics = strcmp(type, "dynamics") == 0;
    for (int i = 0; i < NSCHEMA; i++) {
        const sf_study_key *k = &schema[i];
        if (strchr(k->path, '[') || strchr(k->path, '*')) continue;
        const char *dot = strchr(k->path, '.');
        if (!dot) continue;                         /* top-level keys */
        if (strchr(dot + 1, '.')) continue;         /* deeper: none with defaults */
        char gname[SF_NAME_MAX];
        snprintf(gname, sizeof gname, "%.*s", (int)(dot - k->path), k->path);
        const char *name = dot + 1;
        const sf_study_key *gk = schema_find(gname);
        config_setting_t *g = config_setting_get_member(root, gname);
        if (!g) {
            if (!gk || !(gk->flags & SF_KEY_AUTO)) continue;
            g = config_setting_add(root, gname, CONFIG_TYPE_GROUP);
            if (!g) return sf_fail(err, SF_EINTERNAL, "cannot add %s", gname);
        }
        if (config_setting_get_member(g, name)) continue;
        if ((k->flags & SF_KEY_DYNAMICS) && !dynamics) continue;
        const char *def = k->def;
        char buf[64];
        if (strcmp(k->path, "analysis.end") == 0) {
            const char *param = get_str(an, "parameter", "analysis.parameter");
            snprintf(buf, sizeof buf, "%d.0", strcmp(param, "load") == 0 ? s->nstages : 1);
            def = buf;
        } else if (strcmp(k->path, "analysis.report") == 0) {
            def = s->nprobes ? s->probes[0].name : "";
        }
        if (!def) continue;
        sf_study_key tmp = *k;
        tmp.def = def;
        if (put_default(g, name, &tmp))
            return sf_fail(err, SF_EINTERNAL, "cannot add the default of %s", k->path);
    }
    return SF_OK;
}

/* ---------------------------------------------------------------------- */
/* Load and free                                                           */
/* ---------------------------------------------------------------------- */

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
    {   /* @include relative to the study's directory */
        char dir[1024];
        snprintf(dir, sizeof dir, "%s", path);
        char *sl = strrchr(dir, '/');
        if (sl) { sl[sl == dir ? 1 : 0] = '\0'; config_set_include_dir(cfg, dir); }
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
        int line = find_int_overflow(text, tok, sizeof tok);
        free(text);
        if (line) {
            sf_study_free(s);
            return sf_fail(err, SF_EINPUT,
                           "%s:%d: integer %s is out of range (libconfig would wrap it): write it with a decimal point or an exponent",
                           path, line, tok);
        }
    }

    for (int i = 0; i < nset; i++) {
        rc = apply_set(cfg, sets[i], err);
        if (rc) { sf_study_free(s); return rc; }
    }

    rc = check_group(s, err, config_root_setting(cfg), "");
    if (!rc) rc = fill(s, cfg, err);
    if (!rc) rc = materialize(s, cfg, err);
    if (rc) {
        sf_study_free(s);
        return rc;
    }
    return SF_OK;
}

/* ---------------------------------------------------------------------- */
/* Writer                                                                  */
/* ---------------------------------------------------------------------- */

static void w_double(FILE *f, double x)
{
    char g[40], fx[64];
    int p;
    for (p = 1; p <= 17; p++) {
        snprintf(g, sizeof g, "%.*g", p, x);
        if (strtod(g, NULL) == x) break;
    }
    fx[0] = '\0';
    double ax = fabs(x);
    if (ax == 0 || (ax >= 1e-4 && ax < 1e16)) {
        for (int d = 1; d <= 20; d++) {
            snprintf(fx, sizeof fx, "%.*f", d, x);
            if (strtod(fx, NULL) == x) break;
        }
        /* trim trailing zeros but keep one digit after the point */
        char *pt = strchr(fx, '.');
        if (pt) {
            size_t l = strlen(fx);
            while (l > (size_t)(pt - fx) + 2 && fx[l - 1] == '0') fx[--l] = '\0';
        }
    }
    char *ep = strchr(g, 'e');
    if (ep) {   /* 1.52e+07 -> 1.52e7, 1e-06 -> 1e-6 */
        char *q = ep + 1, *d = ep + 1;
        if (*q == '+') q++;
        else if (*q == '-') { q++; d++; }
        while (*q == '0' && q[1]) q++;
        memmove(d, q, strlen(q) + 1);
    }
    if (!strpbrk(g, ".e")) {
        size_t l = strlen(g);
        snprintf(g + l, sizeof g - l, ".0");
    }
    if (fx[0] && strlen(fx) <= strlen(g)) fputs(fx, f);
    else fputs(g, f);
}

static void w_string(FILE *f, const char *t)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)t; *p; p++) {
        switch (*p) {
        case '"': fputs("\\\"", f); break;
        case '\\': fputs("\\\\", f); break;
        case '\n': fputs("\\n", f); break;
        case '\r': fputs("\\r", f); break;
        case '\t': fputs("\\t", f); break;
        case '\f': fputs("\\f", f); break;
        default:
            if (*p < 0x20) fprintf(f, "\\x%02x", *p);
            else fputc(*p, f);
        }
    }
    fputc('"', f);
}

static void w_inline(FILE *f, const config_setting_t *st)
{
    int n;
    switch (st->type) {
    case CONFIG_TYPE_INT: fprintf(f, "%d", st->value.ival); break;
    case CONFIG_TYPE_INT64: fprintf(f, "%lldL", st->value.llval); break;
    case CONFIG_TYPE_FLOAT: w_double(f, st->value.fval); break;
    case CONFIG_TYPE_BOOL: fputs(st->value.ival ? "true" : "false", f); break;
    case CONFIG_TYPE_STRING: w_string(f, st->value.sval ? st->value.sval : ""); break;
    case CONFIG_TYPE_ARRAY:
    case CONFIG_TYPE_LIST:
        n = config_setting_length(st);
        fputs(st->type == CONFIG_TYPE_ARRAY ? "[" : "(", f);
        for (int i = 0; i < n; i++) {
            fputs(i ? ", " : (st->type == CONFIG_TYPE_LIST ? " " : ""), f);
            w_inline(f, config_setting_get_elem(st, (unsigned)i));
        }
        fputs(st->type == CONFIG_TYPE_ARRAY ? "]" : (n ? " )" : ")"), f);
        break;
    case CONFIG_TYPE_GROUP:
        n = config_setting_length(st);
        fputs("{", f);
        for (int i = 0; i < n; i++) {
            const config_setting_t *m = config_setting_get_elem(st, (unsigned)i);
            fprintf(f, " %s = ", m->name);
            w_inline(f, m);
            fputc(';', f);
        }
        fputs(n ? " }" : "}", f);
        break;
    default: break;
    }
}

/* The --set comments of a subtree: "  # --set a=1; --set b=2" */
static void w_hooks(FILE *f, const config_setting_t *st, int *first)
{
    if (st->hook) {
        fputs(*first ? "  # " : "; ", f);
        for (const char *p = st->hook; *p; p++) fputc(*p == '\n' ? ' ' : *p, f);
        *first = 0;
    }
    if (config_setting_is_aggregate(st)) {
        int n = config_setting_length(st);
        for (int i = 0; i < n; i++) w_hooks(f, config_setting_get_elem(st, (unsigned)i), first);
    }
}

static void w_top(FILE *f, const config_setting_t *st)
{
    int n = config_setting_length(st);
    int first = 1;
    fprintf(f, "%s = ", st->name);
    if (st->type == CONFIG_TYPE_GROUP && n > 0) {
        fputs("{", f);
        if (st->hook) { w_hooks(f, st, &first); }
        fputc('\n', f);
        for (int i = 0; i < n; i++) {
            const config_setting_t *m = config_setting_get_elem(st, (unsigned)i);
            fprintf(f, "  %s = ", m->name);
            w_inline(f, m);
            fputc(';', f);
            int fi = 1;
            w_hooks(f, m, &fi);
            fputc('\n', f);
        }
        fputs("};\n", f);
    } else if (st->type == CONFIG_TYPE_LIST && n > 0) {
        fputs("(", f);
        if (st->hook) { w_hooks(f, st, &first); }
        fputc('\n', f);
        for (int i = 0; i < n; i++) {
            const config_setting_t *m = config_setting_get_elem(st, (unsigned)i);
            fputs("  ", f);
            w_inline(f, m);
            if (i < n - 1) fputc(',', f);
            int fi = 1;
            w_hooks(f, m, &fi);
            fputc('\n', f);
        }
        fputs(");\n", f);
    } else {
        w_inline(f, st);
        fputc(';', f);
        w_hooks(f, st, &first);
        fputc('\n', f);
    }
}

static void w_body(FILE *f, const config_setting_t *root)
{
    int n = config_setting_length(root);
    for (int i = 0; i < n; i++) {
        const config_setting_t *m = config_setting_get_elem(root, (unsigned)i);
        if (i && (config_setting_is_aggregate(m) || config_setting_is_aggregate(config_setting_get_elem(root, (unsigned)i - 1))))
            fputc('\n', f);
        w_top(f, m);
    }
}

int sf_study_print(const sf_study *s, FILE *f, const char *prefix,
                   sf_error *err)
{
    if (!s || !s->cfg) return sf_fail(err, SF_EINTERNAL, "sf_study_print: no study");
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    if (!m) return sf_fail(err, SF_ENOMEM, "out of memory");
    w_body(m, config_root_setting((config_t *)s->cfg));
    if (fclose(m) != 0 || !buf) {
        free(buf);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    if (!prefix) prefix = "";
    for (const char *p = buf; *p;) {
        size_t l = strcspn(p, "\n");
        if (l == 0) {   /* no trailing blanks after the prefix */
            size_t lp = strlen(prefix);
            while (lp && prefix[lp - 1] == ' ') lp--;
            fprintf(f, "%.*s\n", (int)lp, prefix);
        } else {
            fprintf(f, "%s%.*s\n", prefix, (int)l, p);
        }
        p += l;
        if (*p == '\n') p++;
    }
    free(buf);
    if (ferror(f)) return sf_fail(err, SF_EIO, "cannot write the study: %s", strerror(errno));
    return SF_OK;
}

int sf_study_write(const sf_study *s, const char *path,
                   const char *header_comment, sf_error *err)
{
    if (!s || !s->cfg) return sf_fail(err, SF_EINTERNAL, "sf_study_write: no study");
    size_t lp = strlen(path);
    char *tmp = malloc(lp + 5);
    if (!tmp) return sf_fail(err, SF_ENOMEM, "out of memory");
    snprintf(tmp, lp + 5, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        int rc = sf_fail(err, SF_EIO, "%s: cannot write: %s", tmp, strerror(errno));
        free(tmp);
        return rc;
    }
    if (header_comment) {
        const char *p = header_comment;
        while (*p) {
            size_t l = strcspn(p, "\n");
            fprintf(f, "#%s%.*s\n", l ? " " : "", (int)l, p);
            p += l;
            if (*p == '\n') p++;
        }
    }
    w_body(f, config_root_setting((config_t *)s->cfg));
    int bad_write = ferror(f);
    if (fclose(f) != 0) bad_write = 1;
    if (bad_write) {
        int rc = sf_fail(err, SF_EIO, "%s: write failed: %s", tmp, strerror(errno));
        remove(tmp);
        free(tmp);
        return rc;
    }
    if (rename(tmp, path) != 0) {
        int rc = sf_fail(err, SF_EIO, "%s: cannot rename to %s: %s", tmp, path, strerror(errno));
        remove(tmp);
        free(tmp);
        return rc;
    }
    free(tmp);
    return SF_OK;
}

/* ---------------------------------------------------------------------- */
/* Accessors                                                               */
/* ---------------------------------------------------------------------- */

/* Resolve for reading: SF_OK with *node (NULL when absent) and *k. */
static int lookup(const sf_study *s, const char *path, const char *fn,
                  config_setting_t **node, const sf_study_key **k,
                  sf_error *err)
{
    char msg[1024];
    resolved r;
    *node = NULL;
    *k = NULL;
    if (!s || !s->cfg) return sf_fail(err, SF_EINTERNAL, "%s(%s): no study loaded", fn, path);
    if (resolve((config_t *)s->cfg, path, 0, NULL, &r, msg, sizeof msg)) {
        if (strstr(msg, "unknown key") || strstr(msg, "not in the schema"))
            return sf_fail(err, SF_EINTERNAL, "%s(%s): %s; add the key to the schema table in study.c", fn, path, msg);
        return sf_fail(err, SF_EINTERNAL, "%s(%s): %s", fn, path, msg);
    }
    *node = r.node;
    *k = r.key;
    return SF_OK;
}

static int wrong_kind(sf_error *err, const char *fn, const char *path,
                      const sf_study_key *k)
{
    return sf_fail(err, SF_EINTERNAL, "%s(%s): the schema types this key as %s",
                   fn, path, key_type_name(k->type));
}

int sf_study_double(const sf_study *s, const char *path, double def,
                    double *out, sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    int rc = lookup(s, path, "sf_study_double", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_NUMBER) return wrong_kind(err, "sf_study_double", path, k);
    if (!st) {
        if (k->def) parse_def(k->def, &def, 1);
        *out = def;
        return SF_OK;
    }
    char got[128];
    if (!is_num(st)) return bad(s, err, st, "expected a number, got %s", show(st, got, sizeof got));
    double x = numval(st);
    if (!isfinite(x)) return bad(s, err, st, "must be a finite number (got %g)", x);
    *out = x;
    return SF_OK;
}

int sf_study_int(const sf_study *s, const char *path, int def, int *out,
                 sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    int rc = lookup(s, path, "sf_study_int", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_INT) return wrong_kind(err, "sf_study_int", path, k);
    if (!st) {
        if (k->def) { double v; parse_def(k->def, &v, 1); def = (int)v; }
        *out = def;
        return SF_OK;
    }
    char got[128];
    if (st->type == CONFIG_TYPE_INT) { *out = st->value.ival; return SF_OK; }
    if (st->type == CONFIG_TYPE_INT64 && st->value.llval <= INT_MAX && st->value.llval >= INT_MIN) {
        *out = (int)st->value.llval;
        return SF_OK;
    }
    return bad(s, err, st, "expected an integer, got %s", show(st, got, sizeof got));
}

int sf_study_string(const sf_study *s, const char *path, const char *def,
                    const char **out, sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    int rc = lookup(s, path, "sf_study_string", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_STRING) return wrong_kind(err, "sf_study_string", path, k);
    if (!st) { *out = k->def ? k->def : def; return SF_OK; }
    char got[128];
    if (st->type != CONFIG_TYPE_STRING)
        return bad(s, err, st, "expected a string, got %s", show(st, got, sizeof got));
    *out = st->value.sval;
    return SF_OK;
}

int sf_study_bool(const sf_study *s, const char *path, int def, int *out,
                  sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    int rc = lookup(s, path, "sf_study_bool", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_BOOL) return wrong_kind(err, "sf_study_bool", path, k);
    if (!st) {
        if (k->def) { double v; parse_def(k->def, &v, 1); def = v != 0; }
        *out = def;
        return SF_OK;
    }
    char got[128];
    if (st->type != CONFIG_TYPE_BOOL)
        return bad(s, err, st, "expected true or false, got %s", show(st, got, sizeof got));
    *out = st->value.ival != 0;
    return SF_OK;
}

int sf_study_doubles(const sf_study *s, const char *path, int nmin, int nmax,
                     double *out, int *n, sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    *n = 0;
    int rc = lookup(s, path, "sf_study_doubles", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_VEC2 && k->type != SF_KEY_VEC3)
        return wrong_kind(err, "sf_study_doubles", path, k);
    if (!st) {
        if (k->def) *n = parse_def(k->def, out, nmax);
        return SF_OK;
    }
    char got[128];
    if (st->type != CONFIG_TYPE_ARRAY && st->type != CONFIG_TYPE_LIST)
        return bad(s, err, st, "expected an array of numbers, got %s", show(st, got, sizeof got));
    int len = config_setting_length(st);
    if (len < nmin || len > nmax) {
        if (nmin == nmax) return bad(s, err, st, "expected %d numbers, got %d", nmin, len);
        return bad(s, err, st, "expected %d to %d numbers, got %d", nmin, nmax, len);
    }
    for (int i = 0; i < len; i++) {
        const config_setting_t *e = config_setting_get_elem(st, (unsigned)i);
        if (!is_num(e)) return bad(s, err, e, "expected a number, got %s", show(e, got, sizeof got));
        double x = numval(e);
        if (!isfinite(x)) return bad(s, err, e, "must be a finite number (got %g)", x);
        out[i] = x;
    }
    *n = len;
    return SF_OK;
}

int sf_study_has(const sf_study *s, const char *path)
{
    char msg[512];
    resolved r;
    if (!s || !s->cfg) return 0;
    if (resolve((config_t *)s->cfg, path, 0, NULL, &r, msg, sizeof msg)) return 0;
    return r.node != NULL;
}

int sf_study_count(const sf_study *s, const char *path)
{
    char msg[512];
    resolved r;
    if (!s || !s->cfg) return 0;
    if (resolve((config_t *)s->cfg, path, 0, NULL, &r, msg, sizeof msg)) return 0;
    if (!r.node || !config_setting_is_aggregate(r.node)) return 0;
    return config_setting_length(r.node);
}

const char *sf_study_where(const sf_study *s, const char *path, char *buf,
                           size_t n)
{
    char msg[512];
    resolved r;
    if (!s || !s->cfg || !path || resolve((config_t *)s->cfg, path, 0, NULL, &r, msg, sizeof msg)) {
        snprintf(buf, n, "%s", s ? s->path : "");
        return buf;
    }
    const config_setting_t *st = r.node ? r.node : r.parent;
    if (st) where(s, st, buf, n);
    else snprintf(buf, n, "%s", s->path);
    return buf;
}

int sf_study_fail(const sf_study *s, sf_error *err, int code,
                  const char *path, const char *fmt, ...)
{
    char loc[1200], msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    sf_study_where(s, path, loc, sizeof loc);
    if (path && path[0]) return sf_fail(err, code, "%s: %s: %s", loc, path, msg);
    return sf_fail(err, code, "%s: %s", loc, msg);
}

/* ---------------------------------------------------------------------- */
/* Lookups by name                                                         */
/* ---------------------------------------------------------------------- */

int sf_study_vertex_index(const sf_study *s, const char *name)
{
    return s->nvertices ? find_name(name, s->vertices[0].name, sizeof(sf_vertex), s->nvertices) : -1;
}

int sf_study_fold_index(const sf_study *s, const char *name)
{
    if (!name || !name[0]) return -1;
    return s->nfolds ? find_name(name, s->folds[0].name, sizeof(sf_fold_def), s->nfolds) : -1;
}

int sf_study_material_index(const sf_study *s, const char *name)
{
    return s->nmaterials ? find_name(name, s->materials[0].name, sizeof(sf_material), s->nmaterials) : -1;
}

int sf_study_group_index(const sf_study *s, const char *name)
{
    return s->ngroups ? find_name(name, s->groups[0].name, sizeof(sf_group), s->ngroups) : -1;
}

int sf_study_probe_index(const sf_study *s, const char *name)
{
    return s->nprobes ? find_name(name, s->probes[0].name, sizeof(sf_probe), s->nprobes) : -1;
}
