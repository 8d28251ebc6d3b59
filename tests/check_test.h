/* check_test.h - the status and message checks every cmocka test of the
 * library uses (include after cmocka.h). */
#ifndef SF_CHECK_TEST_H
#define SF_CHECK_TEST_H

#include <string.h>

#include "sf_error.h"

/* call returns SF_OK; otherwise print its status and err's message */
#define CHECK_OK(call, err)                                                    \
    do {                                                                       \
        int rc_ = (call);                                                      \
        if (rc_ != SF_OK) {                                                    \
            print_error("expected SF_OK, got %d: %s\n", rc_, (err).msg);       \
            fail();                                                            \
        }                                                                      \
    } while (0)

#define CHECK_CONTAINS(msg, sub)                                               \
    do {                                                                       \
        if (!strstr((msg), (sub))) {                                           \
            print_error("expected a message containing '%s', got '%s'\n", (sub), (msg)); \
            fail();                                                            \
        }                                                                      \
    } while (0)

#endif
