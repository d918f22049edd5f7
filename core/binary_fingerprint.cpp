#include "binary_fingerprint.hpp"

#include <fstream>
#include <vector>

namespace grainlab {

std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < n; ++k) h = (h ^ bytes[k]) * 1099511628211ull;
  return h;
}

std::uint64_t binary_fingerprint() {
  std::ifstream in("/proc/self/exe", std::ios::binary);
  if (!in) return 0;
  std::uint64_t h = kFnvOffsetBasis;
  std::vector<char> buffer(1 << 16);
  while (in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) || in.gcount() > 0)
    h = fnv1a(buffer.data(), static_cast<std::size_t>(in.gcount()), h);
  return h;
}

}  // namespace grainlab
