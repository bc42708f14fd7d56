// ML_ASSERT(condition, message): an invariant that must hold, checked in Debug builds and when
// MANYLIGHT_ASSERTS is defined (the CMake option of that name, on in the sanitizer build); in
// Release builds it compiles to nothing, so it may sit in inner loops. A failed assertion throws
// InternalError naming the condition and the place, which the command line reports like any
// other error (tests see it as an exception, not an abort).
#pragma once

#include <string>

#include "core/error.h"

#if !defined(NDEBUG) || defined(MANYLIGHT_ASSERTS)
#define ML_ASSERTS_ENABLED 1
#define ML_ASSERT(condition, message)                                                     \
    do {                                                                                  \
        if (!(condition))                                                                 \
            throw ::ml::InternalError(std::string("assertion failed: " #condition ": ") + \
                                      (message));                                         \
    } while (false)
#else
#define ML_ASSERTS_ENABLED 0
#define ML_ASSERT(condition, message) \
    do {                              \
    } while (false)
#endif
