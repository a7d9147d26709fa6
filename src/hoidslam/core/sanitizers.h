#pragma once
// Whether this build is instrumented by a sanitizer (scripts/sanitize.sh), for code and tests that must differ
// under one. HOIDSLAM_THREAD_SANITIZER / HOIDSLAM_ADDRESS_SANITIZER are defined for the preprocessor; GCC says
// __SANITIZE_THREAD__ / __SANITIZE_ADDRESS__, clang __has_feature(thread_sanitizer) / (address_sanitizer).

#if defined(__SANITIZE_THREAD__)
#define HOIDSLAM_THREAD_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define HOIDSLAM_THREAD_SANITIZER 1
#endif
#endif

#if defined(__SANITIZE_ADDRESS__)
#define HOIDSLAM_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HOIDSLAM_ADDRESS_SANITIZER 1
#endif
#endif

namespace hoidslam {

#ifdef HOIDSLAM_THREAD_SANITIZER
inline constexpr bool kThreadSanitizer = true;
#else
inline constexpr bool kThreadSanitizer = false;
#endif

#ifdef HOIDSLAM_ADDRESS_SANITIZER
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif

// A sanitized build runs everything several times slower (5–10 × for whole SLAM runs).
inline constexpr bool kSanitized = kThreadSanitizer || kAddressSanitizer;

}  // namespace hoidslam
