#include "kernels/hopfield/hopfield_diagonal.hpp"

#include <algorithm>
#include <cstring>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {

DiagonalCost::DiagonalCost(const NormalisedCost& cost) : n1(cost.n1), n2(cost.n2), n3(cost.n3) {
  require(n1 <= n2 && n1 <= n3, "schedule 'diagonal'", "needs n1 <= n2 and n1 <= n3");
  c.resize(cost.size());
  // Parallel over a: each task writes its own run of blocks (a pure permutation copy, so the
  // result does not depend on the split).
  parallel_for_range(static_cast<std::size_t>(n2), 1, [&](std::size_t ab, std::size_t ae) {
    for (std::size_t a = ab; a < ae; ++a)
      for (int32_t b = 0; b < n3; ++b) {
        float* out = c.data() + (a * n3 + b) * n1;
        int32_t j = static_cast<int32_t>(a), k = b;
        for (int32_t i = 0; i < n1; ++i) {
          out[i] = cost.c[(static_cast<std::size_t>(i) * n2 + j) * n3 + k];
          if (++j == n2) j = 0;
          if (++k == n3) k = 0;
        }
      }
  });
}

std::size_t DiagonalCost::standard_index(int32_t a, int32_t b, int32_t i) const {
  const int32_t j = (i + a) % n2, k = (i + b) % n3;
  return (static_cast<std::size_t>(i) * n2 + j) * n3 + k;
}

DiagonalNetwork::DiagonalNetwork(const HopfieldWeights& w, std::shared_ptr<const DiagonalCost> cost)
    : cost_(std::move(cost)), w_(w), n1_(cost_->n1), n2_(cost_->n2), n3_(cost_->n3) {
  require(w.D == 0.f, "schedule 'diagonal'", "needs D = 0 (the D term couples every neuron)");
  V_.assign(cost_->c.size(), 0);
  R_.assign(n1_, 0.f);
  // Reads reach n2 + (n2 − 1) + (n1 − 1); stores n2 beyond that.
  S_.assign(3 * static_cast<std::size_t>(n2_) + std::max(n1_, 1), 0.f);
  T_.assign(3 * static_cast<std::size_t>(n3_) + std::max(n1_, 1), 0.f);
}

DiagonalNetwork::DiagonalNetwork(const HopfieldWeights& w, const NormalisedCost& c)
    : DiagonalNetwork(w, std::make_shared<const DiagonalCost>(c)) {}

void DiagonalNetwork::set_state(std::span<const uint8_t> V) {
  require(V.size() == cost_->c.size(), "diagonal state", "size does not match n1·n2·n3");
  for (int32_t a = 0; a < n2_; ++a)
    for (int32_t b = 0; b < n3_; ++b) {
      uint8_t* out = V_.data() + (static_cast<std::size_t>(a) * n3_ + b) * n1_;
      int32_t j = a, k = b;
      for (int32_t i = 0; i < n1_; ++i) {
        out[i] = V[(static_cast<std::size_t>(i) * n2_ + j) * n3_ + k];
        if (++j == n2_) j = 0;
        if (++k == n3_) k = 0;
      }
    }
  recompute_sums();
}

void DiagonalNetwork::recompute_sums() {
  std::vector<int32_t> R(n1_, 0), S(n2_, 0), T(n3_, 0);
  for (int32_t a = 0; a < n2_; ++a)
    for (int32_t b = 0; b < n3_; ++b) {
      const uint8_t* v = V_.data() + (static_cast<std::size_t>(a) * n3_ + b) * n1_;
      int32_t j = a, k = b;
      for (int32_t i = 0; i < n1_; ++i) {
        R[i] += v[i];
        S[j] += v[i];
        T[k] += v[i];
        if (++j == n2_) j = 0;
        if (++k == n3_) k = 0;
      }
    }
  for (int32_t i = 0; i < n1_; ++i) R_[i] = static_cast<float>(R[i]);
  for (std::size_t y = 0; y < S_.size(); ++y) S_[y] = static_cast<float>(S[y % n2_]);
  for (std::size_t y = 0; y < T_.size(); ++y) T_[y] = static_cast<float>(T[y % n3_]);
}

void DiagonalNetwork::get_state(std::span<uint8_t> V) const {
  require(V.size() == cost_->c.size(), "diagonal state", "size does not match n1·n2·n3");
  for (int32_t a = 0; a < n2_; ++a)
    for (int32_t b = 0; b < n3_; ++b) {
      const uint8_t* in = V_.data() + (static_cast<std::size_t>(a) * n3_ + b) * n1_;
      int32_t j = a, k = b;
      for (int32_t i = 0; i < n1_; ++i) {
        V[(static_cast<std::size_t>(i) * n2_ + j) * n3_ + k] = in[i];
        if (++j == n2_) j = 0;
        if (++k == n3_) k = 0;
      }
    }
}

// ---------------------------------------------------------------------------------------------
// The scalar reference: the block split into the (at most three) segments where neither
// j = i + a nor k = i + b wraps.

namespace {

// Updates the neurons i ∈ [lo, hi) of one block, j = i + ja, k = i + kb. S and T point at the
// canonical copy (S_ext + n2); the copy n2 later is written too (see the header).
inline int32_t update_segment(int32_t lo, int32_t hi, int32_t ja, int32_t kb, int32_t n2, int32_t n3,
                              const float* __restrict c, uint8_t* __restrict V, float* __restrict R,
                              float* __restrict S, float* __restrict T, float A, float B, float C, float E) {
  int32_t flips = 0;
  const float half = 0.5f * (A + B + C), self = A + B + C;
  for (int32_t i = lo; i < hi; ++i) {
    const float v = static_cast<float>(V[i]);
    // full-plane ΔE_on with primes: A(R−v−½) + B(S−v−½) + C(T−v−½) + E·ĉ (seed 000 Eq. 10 rule below)
    const float dE = A * R[i] + B * S[i + ja] + C * T[i + kb] - self * v - half + E * c[i];
    const float nv = dE < 0.f ? 1.f : (dE > 0.f ? 0.f : v);
    const float d = nv - v;
    R[i] += d;
    S[i + ja] += d;
    S[i + ja + n2] = S[i + ja];
    T[i + kb] += d;
    T[i + kb + n3] = T[i + kb];
    V[i] = static_cast<uint8_t>(nv);
    flips += d != 0.f;
  }
  return flips;
}

}  // namespace

int64_t DiagonalNetwork::update_block_scalar(int32_t a, int32_t b) {
  const std::size_t base = (static_cast<std::size_t>(a) * n3_ + b) * n1_;
  const float* c = cost_->c.data() + base;
  uint8_t* V = V_.data() + base;
  // Segment boundaries where j = i + a or k = i + b wraps.
  int32_t cuts[4] = {0, std::min(n1_, n2_ - a), std::min(n1_, n3_ - b), n1_};
  if (cuts[1] > cuts[2]) std::swap(cuts[1], cuts[2]);
  int64_t flips = 0;
  for (int s = 0; s < 3; ++s) {
    const int32_t lo = cuts[s], hi = cuts[s + 1];
    if (lo >= hi) continue;
    const int32_t ja = lo + a >= n2_ ? a - n2_ : a;
    const int32_t kb = lo + b >= n3_ ? b - n3_ : b;
    flips += update_segment(lo, hi, ja, kb, n2_, n3_, c, V, R_.data(), S_.data() + n2_, T_.data() + n3_, w_.A,
                            w_.B, w_.C, w_.E);
  }
  return flips;
}

int64_t DiagonalNetwork::sweep_reference(std::span<const uint32_t> block_order) {
  int64_t flips = 0;
  for (uint32_t blk : block_order)
    flips += update_block_scalar(static_cast<int32_t>(blk / n3_), static_cast<int32_t>(blk % n3_));
  return flips;
}

// ---------------------------------------------------------------------------------------------
// The vector path.

namespace {

constexpr int32_t L = kDiagonalLanes;
typedef float vfloat __attribute__((vector_size(4 * L)));
typedef int32_t vint __attribute__((vector_size(4 * L)));
typedef uint8_t vbyte __attribute__((vector_size(L)));

inline vfloat load(const float* p) {
  vfloat x;
  std::memcpy(&x, p, sizeof x);
  return x;
}
inline void store(float* p, vfloat x) { std::memcpy(p, &x, sizeof x); }
// m lanes are all-ones or all-zeros (a vector comparison's result).
inline vfloat select(vint m, vfloat x, vfloat y) { return (vfloat)(((vint)x & m) | ((vint)y & ~m)); }

// Steps i = i0 .. i0+L−1 of one block; lanes where `keep` is set stay unchanged (they were done
// by an earlier step of the block). S and T point at the read window (S_ext + n2 + a); the copies n2 before
// and after are written with the same values. Returns the flip mask (−1 per flipped lane).
inline vint block_step(const float* c, uint8_t* V, float* R, float* S, float* T, int32_t n2, int32_t n3,
                       float A, float B, float C, float E, float half, float self, vint keep) {
  vbyte vb;
  std::memcpy(&vb, V, sizeof vb);
  // uint8 → int32 → float: both conversions vectorise (uint8 → float directly does not in GCC 12).
  const vfloat v = __builtin_convertvector(__builtin_convertvector(vb, vint), vfloat);
  const vfloat r = load(R), s = load(S), t = load(T);
  // The same expression as update_segment, so the same rounding.
  const vfloat dE = A * r + B * s + C * t - self * v - half + E * load(c);
  const vfloat one = vfloat{} + 1.f, zero = vfloat{};
  vfloat nv = select(dE < 0.f, one, select(dE > 0.f, zero, v));  // seed 000 Eq. 10
  nv = select(keep, v, nv);
  const vfloat d = nv - v;
  const vfloat s1 = s + d, t1 = t + d;
  store(R, r + d);
  store(S - n2, s1);
  store(S, s1);
  store(S + n2, s1);
  store(T - n3, t1);
  store(T, t1);
  store(T + n3, t1);
  const vbyte nb = __builtin_convertvector(__builtin_convertvector(nv, vint), vbyte);
  std::memcpy(V, &nb, sizeof nb);
  return d != 0.f;
}

}  // namespace

int64_t DiagonalNetwork::sweep(std::span<const uint32_t> block_order) {
  if (n1_ < L) return sweep_reference(block_order);
  const float A = w_.A, B = w_.B, C = w_.C, E = w_.E;
  const float half = 0.5f * (A + B + C), self = A + B + C;
  const int32_t n1 = n1_, n2 = n2_, n3 = n3_;
  const int32_t full = n1 / L * L, rest = n1 - full;
  // With n1 not a multiple of L, the partial end [full, n1) is done first by a step over
  // [n1 − L, n1); the last full step [full − L, full) then keeps its lanes ≥ rest, which that
  // step did. (Tail first: a step that reloads what the step just before it stored would wait for
  // those stores to leave the store buffer.)
  vint keep_last = vint{};
  for (int32_t l = 0; l < L; ++l) keep_last[l] = l >= rest ? -1 : 0;
  const vint keep_none = vint{};
  const float* cost = cost_->c.data();
  float* R = R_.data();
  vint flips = vint{};
  constexpr std::size_t kPrefetchDistance = 4;  // blocks ahead
  const std::size_t nb = block_order.size();
  for (std::size_t p = 0; p < nb; ++p) {
    if (p + kPrefetchDistance < nb) {
      const std::size_t ahead = static_cast<std::size_t>(block_order[p + kPrefetchDistance]) * n1;
      for (int32_t o = 0; o < n1; o += 16) __builtin_prefetch(cost + ahead + o);
      for (int32_t o = 0; o < n1; o += 64) __builtin_prefetch(V_.data() + ahead + o, 1);
    }
    const uint32_t blk = block_order[p];
    const int32_t a = static_cast<int32_t>(blk / n3),
                  b = static_cast<int32_t>(blk - static_cast<uint32_t>(a) * n3);
    const std::size_t base = static_cast<std::size_t>(blk) * n1;
    const float* c = cost + base;
    uint8_t* V = V_.data() + base;
    float* S = S_.data() + n2 + a;
    float* T = T_.data() + n3 + b;
    if (rest) {
      const int32_t i = n1 - L;
      flips -= block_step(c + i, V + i, R + i, S + i, T + i, n2, n3, A, B, C, E, half, self, keep_none);
    }
    for (int32_t i = 0; i < full; i += L)
      flips -= block_step(c + i, V + i, R + i, S + i, T + i, n2, n3, A, B, C, E, half, self,
                          rest && i + L == full ? keep_last : keep_none);
  }
  int64_t total = 0;
  for (int32_t l = 0; l < L; ++l) total += flips[l];
  return total;
}

}  // namespace trackassoc
