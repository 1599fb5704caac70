// DAMPSYM_TEST_ASAN: 1 when this test build runs under AddressSanitizer (the sanitizer build of
// ci/build.sh, -O1: its numerics run several times slower, so a few tests take smaller sizes
// there). GCC defines __SANITIZE_ADDRESS__; clang 14 only answers __has_feature.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define DAMPSYM_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define DAMPSYM_TEST_ASAN 1
#endif
#endif
#ifndef DAMPSYM_TEST_ASAN
#define DAMPSYM_TEST_ASAN 0
#endif
