#include "binary_fingerprint.hpp"

#include <fstream>
#include <vector>

namespace grainlab {

std::uint64_t binary_fingerprint() {
  std::ifstream in("/proc/self/exe", std::ios::binary);
  if (!in) return 0;
  std::uint64_t h = 14695981039346656037ull;
  std::vector<char> buffer(1 << 16);
  while (in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) || in.gcount() > 0) {
    for (std::streamsize k = 0; k < in.gcount(); ++k)
      h = (h ^ static_cast<unsigned char>(buffer[static_cast<std::size_t>(k)])) * 1099511628211ull;
  }
  return h;
}

}  // namespace grainlab
