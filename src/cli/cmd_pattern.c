/* cmd_pattern.c - the crease-pattern commands:
 *   smoothfold pattern NAME [options] -o FILE.cfg|FILE.fold
 *   smoothfold import PATTERN.fold|.svg -o STUDY.cfg|P.fold [--set ...] [options]
 *   smoothfold export STUDY.cfg -o PATTERN.fold [--set ...]
 * Each parses its own options (they differ from the study commands'). */
#define _GNU_SOURCE
#include "commands.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cpattern.h"
#include "fold.h"
#include "foldread.h"
#include "generators.h"
#include "study.h"

static const char *pattern_usage =
    "Usage: smoothfold pattern NAME [OPTION]... -o FILE.cfg|FILE.fold\n"
    "       smoothfold import PATTERN.fold|PATTERN.svg -o STUDY.cfg|P.fold [OPTION]...\n"
    "       smoothfold export STUDY.cfg -o PATTERN.fold [--set KEY=VALUE]...\n"
    "Crease patterns: the classic tessellations (NAME: miura, yoshimura,\n"
    "waterbomb, twist, hypar), FOLD files and SVG drawings in Origami Simulator's\n"
    "colours, written as a ready-to-run study (.cfg) or as FOLD (.fold).\n"
    "docs/guides/patterns.md, docs/guides/importing-patterns.md,\n"
    "docs/reference/svg-format.md.\n"
    "\n"
    "  -o, --output=FILE       the file to write (.cfg: a study; .fold: FOLD)\n"
    "      --cells=MxN         cells along x and y (default 2x2; N alone: NxN;\n"
    "                          hypar: M rings, default 4)\n"
    "      --size=AxB          pattern: panel or cell sizes in m (miura: straight\n"
    "                          side a, zigzag side b; twist: sheet a, central\n"
    "                          square b; hypar: sheet a; A alone: AxA; default\n"
    "                          per pattern)\n"
    "      --size=L            import: the sheet's larger side, in m or with a unit\n"
    "                          (200mm); default: the file's unit, else 200 mm\n"
    "      --angle=DEG         miura: sector angle in degrees (default 60);\n"
    "                          twist: twist angle (default 22.5)\n"
    "      --width=W           band width in m (default 0.1 x the shortest fold)\n"
    "      --fold-angle=DEG    the full (100%) rest angle of folds the pattern gives\n"
    "                          none (import: 180 as Origami Simulator; pattern: 57.3)\n"
    "      --fold-percent=P    how far the run folds: analysis.end = P/100 of the\n"
    "                          target angles, as Origami Simulator's fold percent\n"
    "                          (default 100)\n"
    "      --modes=K           shape modes per fold (defaults.modes, default 1:\n"
    "                          degree-4 vertices lock with 0; import: the\n"
    "                          smallest K >= 1 with more fold coordinates\n"
    "                          than loop rows, 2 for degree-4 vertices)\n"
    "      --drive=GROUP       actuation group driven along the path: mountain,\n"
    "                          valley or all (default all; waterbomb: valley)\n"
    "      --gravity           gravity as load stage 1 (the analysis becomes a load path)\n"
    "      --load=N            a downward point load of N newtons on the probe's face\n"
    "      --include-flat      F (flat, facet) edges become folds (default: facets)\n"
    "      --unit=U            import: coordinate unit (m, cm, mm, um, in, pt, px)\n"
    "      --frame=N           import: the FOLD frame to read (default: the\n"
    "                          crease-pattern frame, else the first flat one)\n"
    "      --angle-sign=S      import: edges_foldAngle's convention: fold (FOLD 1.1,\n"
    "                          valley positive; default), opposite, magnitude\n"
    "                          (unsigned, the sign from the assignment)\n"
    "      --planarize         import FOLD: merge close vertices and split crossing\n"
    "                          edges as for SVG\n"
    "      --merge=TOL         import: merge tolerance, a fraction of the sheet's\n"
    "                          size (default 0.003)\n"
    "      --piece=N           import: of a file that draws several sheets, sheet N\n"
    "                          alone (numbered by area, 1 the largest)\n"
    "      --set KEY=VALUE     override a study setting (as for run)\n";

typedef struct popts {
    const char *output;
    sf_import_opts io;
    int have_fold_angle;
    sf_gen_opts g;
    int have_cells, have_size, have_angle, have_drive;
    sf_cp_study_opts s;
    const char **sets;
    int nset;
    char cmdline[400];   /* the command as typed, for the study's header */
} popts;

static int parse_pair(const char *arg, const char *what, double *x, double *y, sf_error *err)
{
    char *end;
    *x = strtod(arg, &end);
    if (end != arg && !*end) { *y = *x; return SF_OK; }   /* N alone: NxN */
    if (end == arg || (*end != 'x' && *end != 'X'))
        return sf_fail(err, SF_EINPUT, "--%s=%s: expected two numbers joined by 'x', e.g. 2x3", what, arg);
    const char *s = end + 1;
    *y = strtod(s, &end);
    if (end == s || *end)
        return sf_fail(err, SF_EINPUT, "--%s=%s: expected two numbers joined by 'x', e.g. 2x3", what, arg);
    return SF_OK;
}

/* a length in metres, or with a unit: 0.2, 200mm, 8in */
static int parse_length(const char *arg, double *x, sf_error *err)
{
    char *end;
    *x = strtod(arg, &end);
    double m = *end ? sf_unit_metres(end) : 1;
    if (end == arg || !(m > 0) || !isfinite(*x) || !(*x > 0))
        return sf_fail(err, SF_EINPUT, "--size=%s: a positive length in m, or with a unit (200mm, 20cm, 8in)", arg);
    *x *= m;
    return SF_OK;
}

static int parse_num(const char *arg, const char *what, double *x, sf_error *err)
{
    char *end;
    *x = strtod(arg, &end);
    if (end == arg || *end || !isfinite(*x))
        return sf_fail(err, SF_EINPUT, "--%s=%s: not a number", what, arg);
    return SF_OK;
}

/* defaults.width, defaults.setback and fixed_face given with --set size the
 * generated folds too */
static void scan_sets(popts *p)
{
    for (int i = 0; i < p->nset; i++) {
        const char *s = p->sets[i];
        if (strncmp(s, "defaults.width=", 15) == 0) p->s.width = strtod(s + 15, NULL);
        else if (strncmp(s, "defaults.setback=", 17) == 0) p->s.setback_given = 1;
        else if (strncmp(s, "fixed_face=", 11) == 0 &&
                 sscanf(s + 11, " [ %lf , %lf ]", &p->s.fixed[0], &p->s.fixed[1]) == 2)
            p->s.fixed_given = 1;
    }
}

static int parse(int argc, char **argv, popts *p, sf_error *err)
{
    static const struct option lo[] = {
        {"output", required_argument, NULL, 'o'}, {"cells", required_argument, NULL, 'c'},
        {"size", required_argument, NULL, 'z'},   {"angle", required_argument, NULL, 'a'},
        {"width", required_argument, NULL, 'w'},  {"fold-angle", required_argument, NULL, 'f'},
        {"modes", required_argument, NULL, 'k'},  {"gravity", no_argument, NULL, 'g'},
        {"load", required_argument, NULL, 'l'},   {"include-flat", no_argument, NULL, 'F'},
        {"unit", required_argument, NULL, 'u'},   {"frame", required_argument, NULL, 'r'},
        {"set", required_argument, NULL, 's'},    {"help", no_argument, NULL, 'h'},
        {"drive", required_argument, NULL, 'd'},
        {"fold-percent", required_argument, NULL, 'P'}, {"angle-sign", required_argument, NULL, 'S'},
        {"planarize", no_argument, NULL, 'Z'},          {"merge", required_argument, NULL, 'm'},
        {"piece", required_argument, NULL, 'N'},
        {NULL, 0, NULL, 0},
    };
    optind = 1;
    opterr = 0;
    int c;
    double x, y;
    while ((c = getopt_long(argc, argv, "o:h", lo, NULL)) != -1) {
        switch (c) {
        case 'o': p->output = optarg; break;
        case 'c':
            if (parse_pair(optarg, "cells", &x, &y, err)) return err->code;
            if (x != floor(x) || y != floor(y))
                return sf_fail(err, SF_EINPUT, "--cells=%s: whole numbers, e.g. 2x3", optarg);
            p->g.m = (int)x; p->g.n = (int)y; p->have_cells = 1;
            break;
        case 'z':
            if (strcmp(argv[0], "import") == 0) {
                if (parse_length(optarg, &p->io.size, err)) return err->code;
                break;
            }
            if (parse_pair(optarg, "size", &p->g.a, &p->g.b, err)) return err->code;
            p->have_size = 1;
            break;
        case 'P':
            if (parse_num(optarg, "fold-percent", &x, err)) return err->code;
            if (!(x > 0 && x <= 100)) return sf_fail(err, SF_EINPUT, "--fold-percent=%s: must be in (0, 100]", optarg);
            p->s.fold_percent = x;
            break;
        case 'S':
            if (strcmp(optarg, "fold") == 0) p->io.angle_sign = SF_SIGN_FOLD;
            else if (strcmp(optarg, "opposite") == 0) p->io.angle_sign = SF_SIGN_OPPOSITE;
            else if (strcmp(optarg, "magnitude") == 0) p->io.angle_sign = SF_SIGN_MAGNITUDE;
            else return sf_fail(err, SF_EINPUT, "--angle-sign=%s: fold, opposite or magnitude", optarg);
            break;
        case 'Z': p->io.planarize = 1; break;
        case 'N':
            if (parse_num(optarg, "piece", &x, err)) return err->code;
            if (!(x >= 1 && x <= 1e6 && x == floor(x))) return sf_fail(err, SF_EINPUT, "--piece=%s: a whole number from 1", optarg);
            p->io.piece = (int)x;
            break;
        case 'm':
            if (parse_num(optarg, "merge", &x, err)) return err->code;
            if (!(x > 0 && x < 0.1)) return sf_fail(err, SF_EINPUT, "--merge=%s: a fraction of the sheet's size in (0, 0.1)", optarg);
            p->io.merge = x;
            break;
        case 'a': if (parse_num(optarg, "angle", &p->g.angle, err)) return err->code; p->have_angle = 1; break;
        case 'w':
            if (parse_num(optarg, "width", &p->s.width, err)) return err->code;
            if (!(p->s.width > 0)) return sf_fail(err, SF_EINPUT, "--width=%s: must be positive", optarg);
            break;
        case 'f':
            if (parse_num(optarg, "fold-angle", &x, err)) return err->code;
            if (!(x > 0 && x <= 180)) return sf_fail(err, SF_EINPUT, "--fold-angle=%s: must be in (0, 180] degrees", optarg);
            p->s.fold_angle = x * M_PI / 180;
            p->have_fold_angle = 1;
            break;
        case 'k':
            if (parse_num(optarg, "modes", &x, err)) return err->code;
            if (x != floor(x) || x < 0 || x > SF_STUDY_MAX_MODES)
                return sf_fail(err, SF_EINPUT, "--modes=%s: a whole number in 0..%d", optarg, SF_STUDY_MAX_MODES);
            p->s.modes = (int)x;
            break;
        case 'g': p->s.gravity = 1; break;
        case 'l': if (parse_num(optarg, "load", &p->s.load, err)) return err->code; break;
        case 'F': p->s.include_flat = 1; break;
        case 'd':
            if (strcmp(optarg, "mountain") && strcmp(optarg, "valley") && strcmp(optarg, "all"))
                return sf_fail(err, SF_EINPUT, "--drive=%s: mountain, valley or all", optarg);
            p->s.drive = strcmp(optarg, "all") ? optarg : NULL;
            p->have_drive = 1;
            break;
        case 'u':
            if (!(sf_unit_metres(optarg) > 0))
                return sf_fail(err, SF_EINPUT, "--unit=%s: unknown unit (m, cm, mm, um, nm, in, pt, px)", optarg);
            p->io.unit = optarg;
            break;
        case 'r':
            if (parse_num(optarg, "frame", &x, err)) return err->code;
            if (x != floor(x) || x < 0) return sf_fail(err, SF_EINPUT, "--frame=%s: a frame index 0, 1, ...", optarg);
            p->io.frame = (int)x;
            break;
        case 's':
            if (!strchr(optarg, '=')) return sf_fail(err, SF_EINPUT, "--set needs KEY=VALUE");
            p->sets[p->nset++] = optarg;
            break;
        case 'h': fputs(pattern_usage, stdout); return -1;
        default:
            return sf_fail(err, SF_EINPUT, "unknown or incomplete option '%s' (smoothfold %s --help)",
                           argv[optind - 1], argv[0]);
        }
    }
    scan_sets(p);
    return SF_OK;
}

static int ends_with(const char *s, const char *suf)
{
    size_t n = strlen(s), m = strlen(suf);
    return n >= m && strcmp(s + n - m, suf) == 0;
}

static int cmd_pattern(char **argv, popts *p, sf_error *err)
{
    const char *name = argv[optind];
    sf_gen_opts g;
    if (sf_gen_defaults(name, &g, err)) return err->code;
    if (p->have_cells) { g.m = p->g.m; g.n = p->g.n; }
    if (p->have_size) { g.a = p->g.a; g.b = p->g.b; }
    if (p->have_angle) g.angle = p->g.angle;
    g.fold_angle = p->s.fold_angle * 180 / M_PI;
    if (p->have_angle && strcmp(name, "miura") != 0 && strcmp(name, "twist") != 0)
        return sf_fail(err, SF_EINPUT, "pattern %s: --angle applies to miura and twist only", name);
    /* twist and hypar fold only if their faces bend */
    if (strcmp(name, "twist") == 0 || strcmp(name, "hypar") == 0) p->s.bending = 1;
    sf_cpattern cp;
    if (sf_generate(name, &g, &cp, err)) return err->code;
    /* the waterbomb's path from the flat sheet starts with its valleys
     * driven alone (with both groups the exact start does not converge) */
    if (!p->have_drive && strcmp(name, "waterbomb") == 0) p->s.drive = "valley";
    int rc;
    if (ends_with(p->output, ".fold")) {
        rc = sf_fold_write_pattern(&cp, p->output, err);
    } else {
        char hdr[900];
        snprintf(hdr, sizeof hdr, "%s - %s.\n\nGenerated by: %s\n(docs/guides/patterns.md)",
                 cp.title, cp.description, p->cmdline);
        p->s.header = hdr;
        rc = sf_cp_write_study(&cp, &p->s, p->output, p->nset, p->sets, err);
    }
    sf_cp_free(&cp);
    return rc;
}

int sf_cmd_is_pattern(const char *cmd)
{
    return strcmp(cmd, "pattern") == 0 || strcmp(cmd, "import") == 0 || strcmp(cmd, "export") == 0;
}

int sf_cmd_pattern(int argc, char **argv, sf_error *err)
{
    popts p;
    memset(&p, 0, sizeof p);
    sf_cp_study_opts_default(&p.s);
    if (argc > 0 && strcmp(argv[0], "import") == 0) p.s.modes = -1;   /* by the loop rows */
    sf_import_opts_default(&p.io);
    p.sets = calloc((size_t)argc + 1, sizeof *p.sets);
    if (!p.sets) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0; i < argc; i++) {
        size_t l = strlen(p.cmdline);
        snprintf(p.cmdline + l, sizeof p.cmdline - l, "%s%s", i ? " " : "smoothfold ", argv[i]);
    }
    int rc = parse(argc, argv, &p, err);
    if (rc < 0) { free(p.sets); return SF_OK; }
    if (!rc && !p.output) rc = sf_fail(err, SF_EINPUT, "%s: give the output file with -o FILE", argv[0]);
    if (!rc && optind + 1 != argc)
        rc = sf_fail(err, SF_EINPUT, "%s: expected %s", argv[0],
                     strcmp(argv[0], "pattern") == 0 ? "one pattern name (miura, yoshimura, waterbomb, twist, hypar)"
                     : strcmp(argv[0], "import") == 0 ? "one FOLD or SVG file" : "one study file");
    if (rc) { free(p.sets); return SF_CMD_USAGE; }
    if (!rc) {
        if (strcmp(argv[0], "pattern") == 0) {
            if (!ends_with(p.output, ".cfg") && !ends_with(p.output, ".fold")) {
                sf_fail(err, SF_EINPUT, "pattern: -o %s: the output must end in .cfg (a study) or .fold", p.output);
                rc = SF_CMD_USAGE;
            }
            else rc = cmd_pattern(argv, &p, err);
        } else if (strcmp(argv[0], "import") == 0) {
            /* Origami Simulator folds a mountain or valley without an angle to
             * 180 degrees at 100% */
            if (!p.have_fold_angle) p.s.fold_angle = M_PI;
            if (!ends_with(p.output, ".cfg") && !ends_with(p.output, ".fold")) {
                sf_fail(err, SF_EINPUT, "import: -o %s: the output must end in .cfg (a study) or .fold", p.output);
                rc = SF_CMD_USAGE;
            } else
                rc = sf_cmd_import(argc, argv, p.cmdline, p.output, &p.io, &p.s, p.nset, p.sets, err);
        } else if (!ends_with(p.output, ".fold")) {
            sf_fail(err, SF_EINPUT, "export: -o %s: the output must end in .fold", p.output);
            rc = SF_CMD_USAGE;
        } else {
            rc = sf_cmd_export(argc, argv, p.output, p.nset, p.sets, err);
        }
    }
    free(p.sets);
    return rc;
}
