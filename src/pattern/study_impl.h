/* study_impl.h - private to the study files of src/pattern/ (study.c and
 * study_*.c): the functions they share (prefix st_) and the resolved key
 * path.  The public face is study.h.
 *
 * Files of the study reader
 *   study.c         the schema (ONE table of every key) and its queries,
 *                   sf_study_load / sf_study_free, lookups by name
 *   study_util.c    small helpers; where a setting is (file:line or
 *                   --set), key paths of settings, the error messages
 *   study_paths.c   key paths ("a.b[2].c[name]") parsed and resolved in the
 *                   libconfig tree (for --set and the accessors)
 *   study_set.c     --set overrides
 *   study_check.c   integer literals libconfig would wrap, the generic
 *                   check of the tree against the schema, schema defaults
 *                   written into the tree
 *   study_fill.c    semantic checks (names, references, geometry) and the
 *                   plain sf_study of pattern.h filled
 *   study_write.c   the merged study written back (study.cfg of a run)
 *   study_access.c  typed accessors sf_study_double() ... for the modules
 */
#ifndef SF_STUDY_IMPL_H
#define SF_STUDY_IMPL_H

#include <libconfig.h>
#include <stddef.h>

#include "study.h"

typedef struct resolved {
    config_setting_t *parent;   /* existing parent (NULL if absent) */
    config_setting_t *node;     /* the setting, NULL if absent */
    const sf_study_key *key;    /* its schema entry */
    char name[SF_NAME_MAX];     /* member name when the last component is a name */
    char pattern[512];
} resolved;

/* study.c: the schema and its queries; load and free; lookups by name */
const sf_study_key *st_schema_find(const char *pattern);
int st_schema_is_child(const sf_study_key *k, const char *pattern,
                       const char **name);
const char *st_suggest_key(const char *pattern, const char *name,
                           char *buf, size_t n);

/* study_util.c: small helpers; locations, key paths of settings, error messages */
__attribute__((format(printf, 4, 5)))
int st_bad(const sf_study *s, sf_error *err, const config_setting_t *st,
           const char *fmt, ...);
__attribute__((format(printf, 5, 6)))
int st_bad2(const sf_study *s, sf_error *err, const config_setting_t *locst,
            const config_setting_t *st, const char *fmt, ...);
__attribute__((format(printf, 4, 5)))
int st_bad_raw(const sf_study *s, sf_error *err,
               const config_setting_t *st, const char *fmt, ...);
void st_copy_name(char *dst, const char *src);
const char *st_hint(char *buf, size_t n, const char *sugg);
int st_is_filesafe(const char *t);
int st_is_ident(const char *t);
int st_is_num(const config_setting_t *st);
void st_join3(char *dst, size_t n, const char *a, const char *sep,
              const char *b);
const char *st_key_type_name(int t);
void st_keypath(const config_setting_t *st, char *buf, size_t n);
config_setting_t *st_mem(const config_setting_t *g, const char *name);
double st_numval(const config_setting_t *st);
const char *st_show(const config_setting_t *st, char *buf, size_t n);
const char *st_type_name(int t);
void st_where(const sf_study *s, const config_setting_t *st, char *buf,
              size_t n);
char *st_xstrdup(const char *t);

/* study_paths.c: key paths ("a.b[2].c[name]") resolved in the tree */
int st_resolve(config_t *cfg, const char *path, int create,
               const char *hooktext, resolved *r, char *msg, size_t n);

/* study_set.c: --set overrides */
int st_apply_set(config_t *cfg, const char *text, sf_error *err);
void st_set_hook(config_setting_t *st, const char *text);
void st_trim(char *t);

/* study_check.c: integer literals libconfig would wrap; the generic check against the schema; defaults into the tree */
int st_check_group(const sf_study *s, sf_error *err,
                   const config_setting_t *st, const char *pat);
int st_find_int_overflow(const char *p, char *tok, size_t ntok);
int st_materialize(sf_study *s, config_t *cfg, sf_error *err);

/* study_fill.c: semantic checks, filling sf_study */
int st_fill(sf_study *s, config_t *cfg, sf_error *err);
int st_find_name(const char *name, const void *base, size_t stride, int n);
const char *st_get_str(const config_setting_t *g, const char *key,
                       const char *dpattern);
int st_parse_def(const char *def, double *out, int max);

/* study_include.c: every @include of text (and of the files it
 * includes) resolves inside incdir or a folder of SMOOTHFOLD_ALLOW_INCLUDE */
int st_check_includes(const char *path, const char *text, const char *incdir, sf_error *err);

#endif
