/* The checks of the C tests: CHECK(cond, format, ...) counts a check and, when `cond` is false,
 * prints the line, the message and meshmove's last error and counts a failure; STATUS(call,
 * want) checks the status a call returns. A test's exit status is `failures != 0`. */
#ifndef MESHMOVE_TEST_CHECK_H
#define MESHMOVE_TEST_CHECK_H
#include <stdio.h>
#include "meshmove.h"

static int failures = 0, checks = 0;

#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        checks++;                                                                                  \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "line %d: ", __LINE__);                                                \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fprintf(stderr, " [last error: %s]\n", meshmove_last_error());                         \
            failures++;                                                                            \
        }                                                                                          \
    } while (0)
#define STATUS(call, want)                                                                         \
    do {                                                                                           \
        meshmove_status got_ = (call);                                                             \
        CHECK(got_ == (want), "%s returned %s, want %s", #call, meshmove_status_name(got_),       \
              meshmove_status_name(want));                                                         \
    } while (0)

#endif
