// Adam optimiser (see adam.hpp).
#include "kernels/learning/adam.hpp"

#include <cassert>
#include <cmath>
#include <string>

#include "kernels/core/error.hpp"

namespace trackassoc {

void AdamOptions::validate() const {
  require(std::isfinite(learning_rate) && learning_rate > 0, "AdamOptions.learning_rate",
          "must be finite and > 0, got " + std::to_string(learning_rate));
  require(beta1 >= 0 && beta1 < 1, "AdamOptions.beta1", "must be in [0, 1), got " + std::to_string(beta1));
  require(beta2 >= 0 && beta2 < 1, "AdamOptions.beta2", "must be in [0, 1), got " + std::to_string(beta2));
  require(std::isfinite(epsilon) && epsilon > 0, "AdamOptions.epsilon", "must be finite and > 0");
  require(std::isfinite(clip_norm) && clip_norm >= 0, "AdamOptions.clip_norm", "must be finite and >= 0");
  require(std::isfinite(weight_decay) && weight_decay >= 0, "AdamOptions.weight_decay",
          "must be finite and >= 0, got " + std::to_string(weight_decay));
}

template <class S>
double adam_step(std::span<S> params, std::span<const S> grad, AdamState<S>& state, const AdamOptions& o) {
  assert(params.size() == grad.size());
  const std::size_t n = params.size();
  if (state.m.size() != n) {
    state.m.assign(n, S(0));
    state.v.assign(n, S(0));
    state.step = 0;
  }
  double norm2 = 0;
  for (std::size_t k = 0; k < n; ++k) norm2 += static_cast<double>(grad[k]) * grad[k];
  const double norm = std::sqrt(norm2);
  const double scale = (o.clip_norm > 0 && norm > o.clip_norm) ? o.clip_norm / norm : 1.0;
  ++state.step;
  const double c1 = 1.0 - std::pow(o.beta1, static_cast<double>(state.step));
  const double c2 = 1.0 - std::pow(o.beta2, static_cast<double>(state.step));
  const S b1 = static_cast<S>(o.beta1), b2 = static_cast<S>(o.beta2);
  const S step = static_cast<S>(o.learning_rate / c1), inv_sqrt_c2 = static_cast<S>(1.0 / std::sqrt(c2));
  const S eps = static_cast<S>(o.epsilon), sc = static_cast<S>(scale);
  const S decay = static_cast<S>(o.learning_rate * o.weight_decay);  // α·λ (AdamW)
  for (std::size_t k = 0; k < n; ++k) {
    const S g = grad[k] * sc;
    state.m[k] = b1 * state.m[k] + (S(1) - b1) * g;
    state.v[k] = b2 * state.v[k] + (S(1) - b2) * g * g;
    params[k] -= step * state.m[k] / (std::sqrt(state.v[k]) * inv_sqrt_c2 + eps) + decay * params[k];
  }
  return norm;
}

template double adam_step<float>(std::span<float>, std::span<const float>, AdamState<float>&,
                                 const AdamOptions&);
template double adam_step<double>(std::span<double>, std::span<const double>, AdamState<double>&,
                                  const AdamOptions&);

}  // namespace trackassoc
