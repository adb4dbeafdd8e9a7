#pragma once
// HYDROLUX_TEST_ASAN: 1 when the tests (and the CLI they run, built alike) use AddressSanitizer,
// whose shadow memory needs far more address space than an RLIMIT_AS test allows.
#if defined(__SANITIZE_ADDRESS__)
#define HYDROLUX_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HYDROLUX_TEST_ASAN 1
#endif
#endif
#ifndef HYDROLUX_TEST_ASAN
#define HYDROLUX_TEST_ASAN 0
#endif
