/* study.h - read, check, override and write a study (.cfg, libconfig 1.5).
 *
 * A study file describes one scene: the crease pattern, materials, loads,
 * probes, solver settings and the analysis plan (docs/reference/study-keys.md).
 * sf_study_load() reads it, applies "--set key.path=value" overrides,
 * checks every key against ONE schema table (study.c) and fills the plain
 * sf_study of pattern.h.  The libconfig tree stays in s->cfg, completed with
 * the schema defaults, so analysis modules read their own keys with the
 * accessors below, which check type and finiteness again and report the
 * file and line (or the --set option) of a bad value.
 *
 * Every error is one line "<where>: <message>", <where> being
 * "<file>:<line>", "<file>" (no line known) or "--set <key>=<value>".
 *
 * Key paths (accessors, --set, messages): names separated by '.', list
 * elements selected by a 0-based index or, where elements have a `name`
 * key, by that name: "analysis.step", "folds[2].width", "folds[f1].width",
 * "materials.fold.E", "analysis.schedule[0].t".
 */
#ifndef SF_STUDY_H
#define SF_STUDY_H

#include <stddef.h>
#include <stdio.h>

#include "pattern.h"
#include "sf_error.h"

#define SF_STUDY_MAX_MODES 16   /* largest K (defaults.modes, folds[].modes) */

/* ---- schema ------------------------------------------------------------ */

enum sf_key_type {
    SF_KEY_GROUP = 1,   /* { ... } with the member names listed in the table */
    SF_KEY_NAMED,       /* { anyname = ...; ... }: members matched by "path.*" */
    SF_KEY_LIST,        /* ( {...}, {...} ): elements matched by "path[]" */
    SF_KEY_NUMBER,      /* float, or an integer (converted) */
    SF_KEY_INT,         /* integer only */
    SF_KEY_STRING,
    SF_KEY_BOOL,
    SF_KEY_VEC2,        /* [x, y] */
    SF_KEY_VEC3,        /* [x, y, z] */
    SF_KEY_BOOL3,       /* [b, b, b] */
    SF_KEY_NAMES        /* ["a", "b", ...] */
};

enum sf_key_flags {
    SF_KEY_REQUIRED = 1u << 0,  /* must be present when its parent is */
    SF_KEY_GT = 1u << 1,        /* value (each component) > lo */
    SF_KEY_GE = 1u << 2,        /* >= lo */
    SF_KEY_LT = 1u << 3,        /* < hi */
    SF_KEY_LE = 1u << 4,        /* <= hi */
    SF_KEY_IDENT = 1u << 5,     /* string: a name, [A-Za-z_][A-Za-z0-9_-]*, < SF_NAME_MAX */
    SF_KEY_FILESAFE = 1u << 6,  /* string: [A-Za-z0-9_.-]+, < SF_NAME_MAX */
    SF_KEY_AUTO = 1u << 7,      /* group: created (with its defaults) when absent */
    SF_KEY_DYNAMICS = 1u << 8   /* default filled in only for analysis.type "dynamics" */
};

typedef struct sf_study_key {
    const char *path;     /* "folds[].width", "materials.*.E", "solver.quadrature" */
    int type;             /* enum sf_key_type */
    unsigned flags;       /* enum sf_key_flags */
    double lo, hi;        /* bounds used by the GT/GE/LT/LE flags */
    const char *def;      /* default: libconfig text for numbers/vectors/bools
                             ("0.0", "[0.0, 0.0]", "true"), the bare text for
                             strings; NULL when none (or computed in study.c) */
    const char *choices;  /* strings: allowed values separated by '|', or NULL */
    const char *unit;     /* "m", "Pa", "-" ... for the manual */
    const char *doc;      /* one line for the manual and --help */
} sf_study_key;

/* The schema table (for documentation and `smoothfold --keys`). */
const sf_study_key *sf_study_schema(int *n);

/* ---- life cycle -------------------------------------------------------- */

/* Read path, apply the nset overrides "key.path=value" (value in libconfig
 * syntax: 30.4e6, "penalty", [1.0, 2.0], true, { g = [0.0, 0.0, -9.81]; }),
 * check everything and fill s.  On failure s is left empty (safe to free)
 * and err holds one line.  Returns SF_OK, SF_EINPUT, SF_EIO or SF_ENOMEM. */
int sf_study_load(const char *path, int nset, const char *const *sets,
                  sf_study *s, sf_error *err);
void sf_study_free(sf_study *s);

/* Write the merged study (file + overrides + defaults) as a .cfg that
 * sf_study_load reads back to the same values (doubles round-trip exactly).
 * header_comment (may be NULL, may hold several '\n'-separated lines) goes
 * first, each line prefixed by "# ".  Values that came from --set carry a
 * trailing "# --set ..." comment.  Written to "<path>.tmp", then renamed. */
int sf_study_write(const sf_study *s, const char *path,
                   const char *header_comment, sf_error *err);

/* The same merged study into an open stream, every line starting with
 * prefix (e.g. "# " to echo it in an output file's header). */
int sf_study_print(const sf_study *s, FILE *f, const char *prefix,
                   sf_error *err);

/* ---- accessors for analysis modules -------------------------------------
 * path must be in the schema (else SF_EINTERNAL: add it to the table in
 * study.c).  When the key is absent the schema default is returned, or def
 * when the schema has none.  A present value of the wrong type or not
 * finite is SF_EINPUT with "<where>: <path>: ..." in err. */
int sf_study_double(const sf_study *s, const char *path, double def,
                    double *out, sf_error *err);
int sf_study_int(const sf_study *s, const char *path, int def, int *out,
                 sf_error *err);
/* *out points into the study (valid until sf_study_free) or is def. */
int sf_study_string(const sf_study *s, const char *path, const char *def,
                    const char **out, sf_error *err);
/* Replace the value of a string key that is present (a default the
 * program resolved, such as "auto"): DIR/study.cfg then records it.  An
 * absent key stays absent.  Pointers from sf_study_string to its old
 * value become invalid. */
int sf_study_set_string(sf_study *s, const char *path, const char *value, sf_error *err);
int sf_study_bool(const sf_study *s, const char *path, int def, int *out,
                  sf_error *err);
/* An array of numbers (ints accepted) into out[0..nmax-1]; *n = its length.
 * Absent: *n = 0 and SF_OK.  Fewer than nmin or more than nmax: SF_EINPUT. */
int sf_study_doubles(const sf_study *s, const char *path, int nmin, int nmax,
                     double *out, int *n, sf_error *err);
/* 1 when the key is present in the (merged) study, else 0. */
int sf_study_has(const sf_study *s, const char *path);
/* Number of elements of a list/array or members of a group; 0 if absent. */
int sf_study_count(const sf_study *s, const char *path);
/* "<file>:<line>", "<file>" or "--set k=v" for a key path (for messages);
 * returns buf. */
const char *sf_study_where(const sf_study *s, const char *path, char *buf,
                           size_t n);
/* Record "<where of path>: <path>: <message>" in err; returns code. */
int sf_study_fail(const sf_study *s, sf_error *err, int code,
                  const char *path, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));

/* folds[].assignment against the fold's rest angles (assignment.c): a
 * mountain ("M") fold whose rest angle or actuation group's rest angle is
 * positive, or a valley ("V") one with a negative angle, is SF_EINPUT.
 * Called by sf_study_load. */
int sf_study_check_assignments(const sf_study *s, sf_error *err);
/* The sign fold i's assignment gives its angle: +1 valley ("V"), -1
 * mountain ("M"), 0 when it has none (assignment.c). */
double sf_study_fold_sign(const sf_study *s, int i);

/* ---- lookups by name (exact match; -1 when absent) ---------------------- */
int sf_study_vertex_index(const sf_study *s, const char *name);
int sf_study_fold_index(const sf_study *s, const char *name);
int sf_study_material_index(const sf_study *s, const char *name);
int sf_study_group_index(const sf_study *s, const char *name);
int sf_study_probe_index(const sf_study *s, const char *name);

/* Closest candidate to word by edit distance (optimal string alignment,
 * case-insensitive), or NULL when none is close enough to suggest. */
const char *sf_study_suggest(const char *word, int ncand,
                             const char *const *cand);

#endif
