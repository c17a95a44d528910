// Whether this build is instrumented by AddressSanitizer or ThreadSanitizer: g++ says so with __SANITIZE_*__,
// clang 14 only through __has_feature. Tests of memory budgets skip there (the shadow memory is not the
// program's, and ASan's reservation fails under a limit on address space).
#pragma once

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define TWINRAY_SANITIZED_BUILD 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define TWINRAY_SANITIZED_BUILD 1
#endif
#endif
