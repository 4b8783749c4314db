// LDSM_POPCNT_CLONES: compiles a Hamming-distance-heavy function twice on x86 Linux, once with the
// POPCNT instruction and once for the baseline x86-64 (which has none), and picks one at load
// time (GCC/Clang function multi-versioning). Elsewhere it expands to nothing (AArch64 has a
// vector popcount in its baseline).
#pragma once

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
#define LDSM_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_THREAD__) || defined(__SANITIZE_ADDRESS__)
#define LDSM_SANITIZED 1
#endif

#if (defined(__x86_64__) || defined(__i386__)) && defined(__linux__) && \
    (defined(__GNUC__) || defined(__clang__)) && !defined(LDSM_SANITIZED)
// (Sanitizer runtimes start after ifunc resolvers run: no function clones under sanitizers, as
// GCC and clang each announce them.)
#define LDSM_POPCNT_CLONES __attribute__((target_clones("popcnt", "default")))
#else
#define LDSM_POPCNT_CLONES
#endif
