#pragma once
// Whether this build is instrumented by ThreadSanitizer (scripts/sanitize.sh tsan): HOIDSLAM_THREAD_SANITIZER is
// defined then, for code that must differ under it. GCC says __SANITIZE_THREAD__, clang
// __has_feature(thread_sanitizer).

#if defined(__SANITIZE_THREAD__)
#define HOIDSLAM_THREAD_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define HOIDSLAM_THREAD_SANITIZER 1
#endif
#endif
