/* Shared by the C examples: abort with the library's message when a call fails. */
#ifndef MESHMOVE_EXAMPLE_CHECK_H
#define MESHMOVE_EXAMPLE_CHECK_H
#include <stdio.h>
#include <stdlib.h>
#include "meshmove.h"

#define CHECK(call)                                                                        \
    do {                                                                                   \
        meshmove_status st_ = (call);                                                      \
        if (st_ != MESHMOVE_STATUS_OK) {                                                   \
            fprintf(stderr, "%s:%d: %s -> %s: %s\n", __FILE__, __LINE__, #call,            \
                    meshmove_status_name(st_), meshmove_last_error());                     \
            exit(1);                                                                       \
        }                                                                                  \
    } while (0)

#endif
