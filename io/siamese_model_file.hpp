// Siamese BiLSTM model files (HDF5), readable with h5py:
//
//   /  attrs: format = "trackassoc-siamese-model", schema_version = 1, input, hidden, fc,
//             architecture ("siamese", or "lstm" / "bilstm": the concatenated-pair baselines, whose
//             /branch has only /forward for "lstm"),
//             x0, y0, position_scale, t0, time_scale (the input normalisation, kernels/learning/siamese.hpp),
//             training (JSON text: options and results of the training run; may be "{}")
//   /branch/forward/Wx (4H×F), Wh (4H×H), b (4H)      float32, row-major, gate order i, f, g, o
//   /branch/backward/Wx, Wh, b                         (PyTorch nn.LSTM weight_ih/weight_hh layout;
//                                                       its two biases summed into b)
//   /head/W1 (fc×2H), b1 (fc), w2 (fc), b2 (1)
//
// Built on io/hdf5_wrapper.hpp (as the track files): integers and floats of any width are read
// and converted, strings are variable-length UTF-8. Loading reads the file in a forked child first
// (io/isolated_run.hpp, as read_track_file), then checks the format and version, every dataset's
// presence, dtype class and shape, and that all values are finite; errors name the file and the
// dataset. Writing is atomic (io/atomic_file.hpp).
#pragma once

#include <string>

#include "kernels/learning/siamese.hpp"

namespace trackassoc {

void write_siamese_model(const std::string& path, const SiameseModel<float>& model,
                         const std::string& training_json = "{}");

struct LoadedSiameseModel {
  SiameseModel<float> model;
  std::string training_json;
};

LoadedSiameseModel read_siamese_model(const std::string& path);

}  // namespace trackassoc
