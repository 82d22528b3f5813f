#pragma once
// Marks what the shared library libdynrt exports: the API's classes and functions. Everything
// else in the library is built with hidden visibility, so the engine's internals are not part
// of its ABI.

#if defined(__GNUC__) || defined(__clang__)
#define DYNRT_API __attribute__((visibility("default")))
#else
#define DYNRT_API
#endif
