/* assignment.c - folds[].assignment ("M" mountain, "V" valley) against the
 * signs of the fold's rest angles.  The sign convention is FOLD's: a
 * valley fold has a positive fold angle (docs/reference/study-keys.md, "Sign of
 * a fold angle"), so a mountain fold driven to a positive rest angle is a
 * sign error, caught here when the study is loaded. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "study.h"

int sf_study_check_assignments(const sf_study *s, sf_error *err)
{
    for (int i = 0; i < s->nfolds; i++) {
        char key[64];
        snprintf(key, sizeof key, "folds[%d].assignment", i);
        if (!sf_study_has(s, key)) continue;
        const char *a = NULL;
        int rc = sf_study_string(s, key, "", &a, err);
        if (rc) return rc;
        double sg = strcmp(a, "V") == 0 ? 1.0 : -1.0;
        const char *what = sg > 0 ? "valley (\"V\": fold angles >= 0)" : "mountain (\"M\": fold angles <= 0)";
        const sf_fold_def *f = &s->folds[i];
        if (f->rest_angle * sg < 0)
            return sf_study_fail(s, err, SF_EINPUT, key,
                                 "a %s fold with rest_angle %g rad: wrong sign (valley positive, "
                                 "docs/reference/study-keys.md)", what, f->rest_angle);
        if (f->group >= 0 && s->groups[f->group].rest_angle * sg < 0)
            return sf_study_fail(s, err, SF_EINPUT, key,
                                 "a %s fold in actuation group '%s' whose rest_angle is %g rad: wrong "
                                 "sign (valley positive, docs/reference/study-keys.md)", what,
                                 s->groups[f->group].name, s->groups[f->group].rest_angle);
    }
    return SF_OK;
}

double sf_study_fold_sign(const sf_study *s, int i)
{
    if (i < 0 || i >= s->nfolds) return 0.0;
    char key[64];
    snprintf(key, sizeof key, "folds[%d].assignment", i);
    if (!sf_study_has(s, key)) return 0.0;
    const char *a = NULL;
    sf_error e;
    sf_error_clear(&e);
    if (sf_study_string(s, key, "", &a, &e) || !a) return 0.0;
    return strcmp(a, "V") == 0 ? 1.0 : strcmp(a, "M") == 0 ? -1.0 : 0.0;
}
