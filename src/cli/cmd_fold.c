/* cmd_fold.c - smoothfold import / export (FOLD files). */
#include "commands.h"

#include "cpattern.h"

int sf_cmd_import(int argc, char **argv, const char *output, const char *unit,
                  int frame, struct sf_cp_study_opts *so, int nset,
                  const char **sets, sf_error *err)
{
    (void)argc; (void)argv; (void)output; (void)unit; (void)frame; (void)so; (void)nset; (void)sets;
    return sf_fail(err, SF_EINPUT, "import: not yet");
}

int sf_cmd_export(int argc, char **argv, const char *output, int nset,
                  const char **sets, sf_error *err)
{
    (void)argc; (void)argv; (void)output; (void)nset; (void)sets;
    return sf_fail(err, SF_EINPUT, "export: not yet");
}
