#pragma once
// A fingerprint of the running program's own file, for results kept to be taken up by a later run
// (`validate --resume`, `cost --resume`): a rebuilt binary may give other numbers, so its results are not
// mixed with the old one's.
#include <cstddef>
#include <cstdint>

namespace grainlab {

// FNV-1a over `n` bytes, continuing from `h` (the offset basis for a fresh hash).
inline constexpr std::uint64_t kFnvOffsetBasis = 14695981039346656037ull;
std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h = kFnvOffsetBasis);

// FNV-1a over the bytes of /proc/self/exe (0 where that cannot be read).
std::uint64_t binary_fingerprint();

}  // namespace grainlab
