/* cmd_keys.c - `smoothfold keys`: the study keys of the schema (study.c),
 * one per line, for the shell's completion and for a user who wants the
 * list without the manual.  With --verbose also each key's type, default,
 * allowed values, unit and its line of documentation, tab-separated. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "study.h"

static const char *type_name(int type)
{
    switch (type) {
    case SF_KEY_NUMBER: return "number";
    case SF_KEY_INT: return "integer";
    case SF_KEY_STRING: return "string";
    case SF_KEY_BOOL: return "bool";
    case SF_KEY_VEC2: return "[x, y]";
    case SF_KEY_VEC3: return "[x, y, z]";
    case SF_KEY_BOOL3: return "[b, b, b]";
    case SF_KEY_NAMES: return "[names]";
    default: return "group";
    }
}

static const char *keys_help =
    "Usage: smoothfold keys [--verbose]\n"
    "List the study keys that hold a value (groups and lists left out), one per\n"
    "line, in the schema's order.  folds[].width is a key of every element of\n"
    "the list folds, materials.*.E one of every named material.\n"
    "--verbose: tab-separated path, type, default, allowed values, unit and the\n"
    "key's one line of documentation (docs/reference/study-keys.md has more).\n"
    "Exit status: 0 listed, 2 usage error.\n";

int sf_cmd_keys(int argc, char **argv)
{
    int verbose = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "-v") == 0 || strcmp(argv[i], "--verbose") == 0) verbose = 1;
        else if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) {
            fputs(keys_help, stdout);
            return 0;
        } else {
            fprintf(stderr, "smoothfold: keys: unknown argument '%s' (try 'smoothfold keys --help')\n",
                    argv[i]);
            return 2;
        }
    }
    int n;
    const sf_study_key *k = sf_study_schema(&n);
    for (int i = 0; i < n; i++) {
        if (k[i].type == SF_KEY_GROUP || k[i].type == SF_KEY_NAMED || k[i].type == SF_KEY_LIST)
            continue;
        if (!verbose) {
            printf("%s\n", k[i].path);
            continue;
        }
        printf("%s\t%s\t%s\t%s\t%s\t%s\n", k[i].path, type_name(k[i].type), k[i].def ? k[i].def : "",
               k[i].choices ? k[i].choices : "", k[i].unit ? k[i].unit : "", k[i].doc ? k[i].doc : "");
    }
    return 0;
}
