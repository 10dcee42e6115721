// Whether this build runs under AddressSanitizer or ThreadSanitizer, where the slowest checks
// (the perceptual metric's image path over many stimuli) run on a subset of their cases.
#pragma once

namespace foveart::test {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kUnderSanitizer = true;
#else
inline constexpr bool kUnderSanitizer = false;
#endif

}  // namespace foveart::test
