/* fuzz_import.c - libFuzzer target: the crease-pattern readers on
 * arbitrary bytes, FOLD (jansson) when built with -DSF_FUZZ_SVG=0, SVG
 * (libxml2) with -DSF_FUZZ_SVG=1; each input is read as `smoothfold
 * import` reads a file (sf_import_read: the reader, the size, the
 * planarizing of SVG, the choice of one sheet of several (--piece=1 for
 * one input in three, by its length), the planar-graph check) and, for
 * one input in eight that reads, written as a study as `import` writes it
 * (folds that end inside a face left out, sf_cp_drop_dangling; then
 * sf_cp_write_study: fold chains, setbacks, the study written, read back
 * and its topology built).
 *
 * Any outcome is fine except a crash, a sanitizer report, a leak or a
 * hang: a bad input must come back as an error status with a one-line
 * message (SF_FUZZ_ONE_LINE=0 in the environment skips the one-line
 * check).  Built and run by tests/fuzz/run.sh.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cpattern.h"
#include "foldread.h"

#ifndef SF_FUZZ_SVG
#define SF_FUZZ_SVG 0
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_message(int rc, const sf_error *err)
{
    const char *one = getenv("SF_FUZZ_ONE_LINE");
    if (rc != SF_OK && (err->code == SF_OK || err->msg[0] == '\0' ||
                        (!(one && one[0] == '0') && strchr(err->msg, '\n')))) {
        fprintf(stderr, "fuzz_import: status %d with message '%s'\n", rc, err->msg);
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char dir[64], path[96], out[112];
    /* in memory where there is a tmpfs: the file system is the cost */
    struct stat st;
    const char *base = stat("/dev/shm", &st) == 0 && S_ISDIR(st.st_mode) ? "/dev/shm" : "/tmp";
    snprintf(dir, sizeof dir, "%s/sf-fuzz-%ld", base, (long)getpid());
    snprintf(path, sizeof path, "%s/in.%s", dir, SF_FUZZ_SVG ? "svg" : "fold");
    snprintf(out, sizeof out, "%s/out.cfg", dir);
    FILE *f = fopen(path, "wb");
    if (!f && mkdir(dir, 0700) == 0) f = fopen(path, "wb");
    if (!f) abort();
    if (size && fwrite(data, 1, size, f) != size) abort();
    if (fclose(f) != 0) abort();

    sf_import_opts io;
    sf_import_opts_default(&io);
    io.piece = size % 3 == 1 ? 1 : 0;
    sf_cpattern cp;
    sf_import_info info;
    sf_error err;
    sf_error_clear(&err);
    int rc = sf_import_read(path, &io, &cp, &info, &err);
    check_message(rc, &err);
    if (rc == SF_OK) {
        /* the study for one input in eight (by its length: the same input
         * always takes the same path) of moderate size: writing and reading
         * the study back costs five times the reading */
        if ((size & 7) == 0 && cp.ne <= 100) {
            sf_cp_study_opts so;
            sf_cp_study_opts_default(&so);
            sf_error_clear(&err);
            rc = sf_cp_drop_dangling(&cp, 0, NULL, 0, &err) < 0 ? err.code : SF_OK;
            check_message(rc, &err);
            if (rc == SF_OK) {
                rc = sf_cp_write_study(&cp, &so, out, 0, NULL, &err);
                check_message(rc, &err);
            }
            remove(out);
        }
        sf_cp_free(&cp);
    }
    return 0;
}
