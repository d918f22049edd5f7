#pragma once
// Four doubles at a time (GCC vector extensions: one AVX register, or two SSE2 ones without AVX), for the
// sphere kernel's pairs (sphere_pair_batch.hpp) and turns (world3d_detail.hpp). Each lane is plain IEEE
// arithmetic, so a lane gives the bits scalar code gives for the same operations in the same order.
#include <cmath>
#include <cstdint>
#include <cstring>

#ifdef __AVX__
#include <immintrin.h>
#endif

#include "world_types.hpp"

namespace grainlab::dem {

namespace lanes4 {
typedef double V4 __attribute__((vector_size(32)));
typedef long long M4 __attribute__((vector_size(32)));

inline V4 splat(double a) {
  return V4{a, a, a, a};
}
inline V4 sqrt(V4 a) {
#ifdef __AVX__
  return _mm256_sqrt_pd(a);
#else
  return V4{std::sqrt(a[0]), std::sqrt(a[1]), std::sqrt(a[2]), std::sqrt(a[3])};
#endif
}
inline V4 pick(M4 m, V4 a, V4 b) {  // a where m is set, else b
  return m ? a : b;
}
inline bool any(M4 m) {
#ifdef __AVX__
  return _mm256_movemask_pd(_mm256_castsi256_pd(__m256i(m))) != 0;
#else
  return (m[0] | m[1] | m[2] | m[3]) != 0;
#endif
}
inline V4 load(const double* p) {
  V4 a;
  std::memcpy(&a, p, sizeof a);
  return a;
}
inline void store(double* p, V4 a) {
  std::memcpy(p, &a, sizeof a);
}
// Three components as three registers of four lanes.
struct T4 {
  V4 x, y, z;
};
inline T4 operator+(const T4& a, const T4& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline T4 operator-(const T4& a, const T4& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline T4 operator*(V4 s, const T4& a) {
  return {s * a.x, s * a.y, s * a.z};
}
inline V4 dot(const T4& a, const T4& b) {  // (a0 b0 + a1 b1) + a2 b2, as Eigen and the scalar kernel
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
inline T4 cross(const T4& a, const T4& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline T4 pick(M4 m, const T4& a, const T4& b) {
  return {pick(m, a.x, b.x), pick(m, a.y, b.y), pick(m, a.z, b.z)};
}
// The vectors at four indices, one to a lane.
inline T4 gather(const Vec3* p, const std::uint32_t* at) {
  const Vec3 &a = p[at[0]], &b = p[at[1]], &c = p[at[2]], &d = p[at[3]];
  return {V4{a.x(), b.x(), c.x(), d.x()}, V4{a.y(), b.y(), c.y(), d.y()}, V4{a.z(), b.z(), c.z(), d.z()}};
}
// Scalars at four indices: from an array, or from anything indexed as one.
template <class Column>
inline V4 gather(const Column& p, const std::uint32_t* at) {
  return V4{p[at[0]], p[at[1]], p[at[2]], p[at[3]]};
}
}  // namespace lanes4

}  // namespace grainlab::dem
