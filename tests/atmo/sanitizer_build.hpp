// Whether this test binary is built with AddressSanitizer: such builds run ~10x slower,
// so Monte-Carlo tests take fewer paths there and assert bounds that widen with their
// standard errors.
#pragma once

namespace atmosh::test {
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif
}  // namespace atmosh::test
