/* fuzz_study.c - libFuzzer target: the study reader, the topology and the
 * model construction (sf_scene_open) on arbitrary bytes as a study file.
 *
 * Any outcome is fine except a crash, a sanitizer report, a leak or a
 * hang: a bad input must come back as an error status with a one-line
 * message (SF_FUZZ_ONE_LINE=0 in the environment skips the one-line check).
 * Built and run by tests/fuzz/run.sh
 * (clang -fsanitize=fuzzer,address).
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* the reader takes a path: one scratch file per process, in a
     * directory of its own (an @include finds nothing else there) */
    char dir[64], path[96];
    /* in memory where there is a tmpfs: the file system is the cost */
    struct stat st;
    const char *base = stat("/dev/shm", &st) == 0 && S_ISDIR(st.st_mode) ? "/dev/shm" : "/tmp";
    snprintf(dir, sizeof dir, "%s/sf-fuzz-%ld", base, (long)getpid());
    snprintf(path, sizeof path, "%s/in.cfg", dir);
    FILE *f = fopen(path, "wb");
    if (!f && mkdir(dir, 0700) == 0) f = fopen(path, "wb");
    if (!f) abort();
    if (size && fwrite(data, 1, size, f) != size) abort();
    if (fclose(f) != 0) abort();

    sf_scene sc;
    sf_error err;
    sf_error_clear(&err);
    int rc = sf_scene_open(&sc, path, 0, NULL, &err);
    const char *one = getenv("SF_FUZZ_ONE_LINE");
    if (rc != SF_OK && (err.code == SF_OK || err.msg[0] == '\0' ||
                        (!(one && one[0] == '0') && strchr(err.msg, '\n')))) {
        fprintf(stderr, "fuzz_study: status %d with message '%s'\n", rc, err.msg);
        abort();
    }
    sf_scene_close(&sc);
    return 0;
}
