// DNG_SANITIZED_BUILD: defined in a build with AddressSanitizer or ThreadSanitizer (GCC defines the
// __SANITIZE_* names, clang answers __has_feature). Their runtimes own operator new and map much of the
// address space, so dngbake's memory limit (memory_cap.cpp) stays out of such builds, and the tests that
// need it, or an address-space limit, skip there.
#pragma once

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define DNG_SANITIZED_BUILD 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define DNG_SANITIZED_BUILD 1
#endif
#endif
