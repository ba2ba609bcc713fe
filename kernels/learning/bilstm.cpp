// BiLSTM forward and BPTT (see bilstm.hpp for the equations and the masking rule).
#include "kernels/learning/bilstm.hpp"

#include <cassert>

namespace trackassoc {
namespace {

template <class S>
struct LstmViews {
  Eigen::Map<const MatrixX<S>> wx, wh;
  Eigen::Map<const VectorX<S>> b;
  LstmViews(const S* p, const LstmShape& s)
      : wx(p, 4 * s.hidden, s.input),
        wh(p + 4 * s.hidden * s.input, 4 * s.hidden, s.hidden),
        b(p + 4 * s.hidden * s.input + 4 * s.hidden * s.hidden, 4 * s.hidden) {}
};

template <class S>
struct LstmGradViews {
  Eigen::Map<MatrixX<S>> wx, wh;
  Eigen::Map<VectorX<S>> b;
  LstmGradViews(S* p, const LstmShape& s)
      : wx(p, 4 * s.hidden, s.input),
        wh(p + 4 * s.hidden * s.input, 4 * s.hidden, s.hidden),
        b(p + 4 * s.hidden * s.input + 4 * s.hidden * s.hidden, 4 * s.hidden) {}
};

template <class S>
inline S logistic(S a) {
  return S(1) / (S(1) + std::exp(-a));
}

}  // namespace

template <class S>
void lstm_forward(const S* params, const LstmShape& shape, const SequenceBatch<S>& x, bool reverse,
                  MatrixX<S>& h_final, LstmCache<S>* cache) {
  const int H = shape.hidden, T = x.length(), B = x.batch();
  assert(x.features() == shape.input);
  const LstmViews<S> w(params, shape);
  MatrixX<S> h = MatrixX<S>::Zero(H, B), c = MatrixX<S>::Zero(H, B);
  MatrixX<S> a(4 * H, B), c_new(H, B), c_tanh(H, B);
  if (cache) {
    cache->gates.resize(T);
    cache->c.resize(T);
    cache->h.resize(T);
    cache->c_tanh.resize(T);
  }
  for (int s = 0; s < T; ++s) {
    const int t = reverse ? T - 1 - s : s;
    a.noalias() = w.wx * x.steps[t];
    a.noalias() += w.wh * h;
    a.colwise() += w.b;
    // Activate in place: rows [0,H) i, [H,2H) f, [2H,3H) g, [3H,4H) o.
    a.topRows(2 * H) = a.topRows(2 * H).unaryExpr([](S v) { return logistic(v); });
    a.middleRows(2 * H, H) = a.middleRows(2 * H, H).array().tanh();
    a.bottomRows(H) = a.bottomRows(H).unaryExpr([](S v) { return logistic(v); });
    c_new = a.middleRows(H, H).cwiseProduct(c) + a.topRows(H).cwiseProduct(a.middleRows(2 * H, H));
    c_tanh = c_new.array().tanh();
    // Masked update: a padded step keeps the previous state (bilstm.hpp, Masking).
    for (int b = 0; b < B; ++b) {
      if (x.mask(t, b) != S(0)) {
        c.col(b) = c_new.col(b);
        h.col(b) = a.bottomRows(H).col(b).cwiseProduct(c_tanh.col(b));
      }
    }
    if (cache) {
      cache->gates[s] = a;
      cache->c[s] = c;
      cache->h[s] = h;
      cache->c_tanh[s] = c_tanh;
    }
  }
  h_final = h;
}

template <class S>
void lstm_backward(const S* params, const LstmShape& shape, const SequenceBatch<S>& x, bool reverse,
                   const LstmCache<S>& cache, const MatrixX<S>& dh_final, S* grad) {
  const int H = shape.hidden, T = x.length(), B = x.batch();
  const LstmViews<S> w(params, shape);
  LstmGradViews<S> g(grad, shape);
  MatrixX<S> dh = dh_final, dc = MatrixX<S>::Zero(H, B);
  MatrixX<S> da(4 * H, B), dct(H, B), dht(H, B);
  const MatrixX<S> zero = MatrixX<S>::Zero(H, B);
  for (int s = T - 1; s >= 0; --s) {
    const int t = reverse ? T - 1 - s : s;
    const auto m = x.mask.row(t).array();  // 1×B
    const MatrixX<S>& gates = cache.gates[s];
    const MatrixX<S>& c_prev = s > 0 ? cache.c[s - 1] : zero;
    const MatrixX<S>& h_prev = s > 0 ? cache.h[s - 1] : zero;
    const auto gi = gates.topRows(H).array();
    const auto gf = gates.middleRows(H, H).array();
    const auto gg = gates.middleRows(2 * H, H).array();
    const auto go = gates.bottomRows(H).array();
    const auto ct = cache.c_tanh[s].array();
    // Only valid columns flow into the cell; padded columns pass dh, dc through unchanged.
    dht.array() = dh.array().rowwise() * m;
    dct.array() = dc.array().rowwise() * m + dht.array() * go * (S(1) - ct * ct);  // dL/dc̃
    da.topRows(H).array() = dct.array() * gg * gi * (S(1) - gi);
    da.middleRows(H, H).array() = dct.array() * c_prev.array() * gf * (S(1) - gf);
    da.middleRows(2 * H, H).array() = dct.array() * gi * (S(1) - gg * gg);
    da.bottomRows(H).array() = dht.array() * ct * go * (S(1) - go);
    g.wx.noalias() += da * x.steps[t].transpose();
    g.wh.noalias() += da * h_prev.transpose();
    g.b.noalias() += da.rowwise().sum();
    const auto keep = (S(1) - m);
    dc.array() = dct.array() * gf + dc.array().rowwise() * keep;
    MatrixX<S> dh_prev = w.wh.transpose() * da;
    dh.array() = dh_prev.array() + dh.array().rowwise() * keep;
  }
}

template <class S>
void bilstm_forward(const S* params, const LstmShape& shape, const SequenceBatch<S>& x, MatrixX<S>& embedding,
                    BiLstmCache<S>* cache) {
  const int H = shape.hidden;
  MatrixX<S> hf, hb;
  lstm_forward(params, shape, x, false, hf, cache ? &cache->forward : nullptr);
  lstm_forward(params + shape.parameter_count(), shape, x, true, hb, cache ? &cache->backward : nullptr);
  embedding.resize(2 * H, x.batch());
  embedding.topRows(H) = hf;
  embedding.bottomRows(H) = hb;
}

template <class S>
void bilstm_backward(const S* params, const LstmShape& shape, const SequenceBatch<S>& x,
                     const BiLstmCache<S>& cache, const MatrixX<S>& d_embedding, S* grad) {
  const int H = shape.hidden;
  const MatrixX<S> dhf = d_embedding.topRows(H), dhb = d_embedding.bottomRows(H);
  lstm_backward(params, shape, x, false, cache.forward, dhf, grad);
  lstm_backward(params + shape.parameter_count(), shape, x, true, cache.backward, dhb,
                grad + shape.parameter_count());
}

#define TRACKASSOC_INSTANTIATE_BILSTM(S)                                                                \
  template void lstm_forward<S>(const S*, const LstmShape&, const SequenceBatch<S>&, bool, MatrixX<S>&, \
                                LstmCache<S>*);                                                         \
  template void lstm_backward<S>(const S*, const LstmShape&, const SequenceBatch<S>&, bool,             \
                                 const LstmCache<S>&, const MatrixX<S>&, S*);                           \
  template void bilstm_forward<S>(const S*, const LstmShape&, const SequenceBatch<S>&, MatrixX<S>&,     \
                                  BiLstmCache<S>*);                                                     \
  template void bilstm_backward<S>(const S*, const LstmShape&, const SequenceBatch<S>&,                 \
                                   const BiLstmCache<S>&, const MatrixX<S>&, S*);

TRACKASSOC_INSTANTIATE_BILSTM(float)
TRACKASSOC_INSTANTIATE_BILSTM(double)

}  // namespace trackassoc
