// The pybind11 module trackassoc._core (docs/design.md §9; the package is engine/python/trackassoc/):
// associate, fuse, evaluate, read and write over the engine's own association interface
// (engine/pipeline/associator.hpp), track fuser and schema v1 io, so an array or a file is
// validated, associated and written by the code the command line runs, with the same results,
// bit for bit. Every function releases the GIL while the engine works; threads= limits oneTBB
// with tbb::global_control for the call (process-wide, as --threads: two concurrent calls with
// different threads= share the smaller limit while both run). InputError is ValueError.
#include <oneapi/tbb/global_control.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>

#include "engine/fusion/track_fuser.hpp"
#include "engine/pipeline/associator_fields.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/python/arrays.hpp"
#include "engine/python/results.hpp"
#include "engine/version.hpp"

namespace trackassoc::python {

namespace {

// threads=None: every core; else an int >= 1, the oneTBB workers for the scope of the object.
class ThreadLimit {
 public:
  explicit ThreadLimit(const py::object& threads) {
    if (threads.is_none()) return;
    if (!py::isinstance<py::int_>(threads) || py::isinstance<py::bool_>(threads) ||
        threads.cast<py::int_>().attr("__lt__")(1).cast<bool>() ||
        threads.cast<py::int_>().attr("__gt__")(1 << 16).cast<bool>())
      throw InputError("threads: expected None or an integer in [1, 65536], got " +
                       py::repr(threads).cast<std::string>());
    n_ = threads.cast<int>();
  }
  // Made with the GIL released (global_control may wait for the arena's workers).
  std::unique_ptr<tbb::global_control> apply() const {
    if (n_ <= 0) return nullptr;
    return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                 static_cast<std::size_t>(n_));
  }

 private:
  int n_ = 0;
};

// A TrackFile object as is (sensors must then be None), or arrays made into a validated one.
std::shared_ptr<const TrackFile> track_file_of(const py::handle& tracks, const py::handle& sensors) {
  if (py::isinstance<PyTrackFile>(tracks)) {
    if (!sensors.is_none())
      throw InputError("sensors: a TrackFile has its own /sensors; give sensors= only with arrays");
    return tracks.cast<const PyTrackFile&>().file;
  }
  return std::make_shared<const TrackFile>(track_file_from_python(tracks, sensors));
}

PyAssociation associate(const py::object& tracks, const py::object& sensors, const py::object& threads,
                        const py::kwargs& options) {
  const ThreadLimit limit(threads);
  AssociatorOptions request = read_associator_options(json_from_python(options, "associate"), "associate");
  if (request.siamese_model.empty()) request.siamese_model = TRACKASSOC_DATA_DIR "/models/siamese_seed003.h5";
  std::shared_ptr<const TrackFile> file = track_file_of(tracks, sensors);
  PyAssociation result;
  result.computed = true;
  {
    py::gil_scoped_release release;
    const auto control = limit.apply();
    std::unique_ptr<TrackAssociator> associator;
    {
      const std::lock_guard<std::mutex> hdf5(hdf5_mutex());  // siamese reads its model file
      associator = make_associator(request);
    }
    // Track hygiene as `associate` does it: a recycled track number becomes new local tracks, and the
    // association's `tracks` is then the split file (source_track keeps the recorded numbers).
    TrackFile split = *file;
    const TrackSplitSummary cuts = split_recorded_keys(split, request);
    if (cuts.any()) file = std::make_shared<const TrackFile>(std::move(split));
    result.outcome = associator->associate(*file);
    result.outcome.summary.split = cuts;
  }
  result.input = file;
  return result;
}

py::dict evaluate(const PyAssociation& association, const py::object& tracks) {
  std::shared_ptr<const TrackFile> file =
      tracks.is_none() ? association.input : track_file_of(tracks, py::none());
  AssociationMetrics m;
  {
    py::gil_scoped_release release;
    m = evaluate_association(file->tracks, file->sensors, association.outcome.record);
  }
  if (!m.has_truth)
    throw InputError("evaluate: /tracks/truth holds no target ids (-1 everywhere); nothing to evaluate");
  py::dict d;
  d["targets"] = m.targets;
  d["correct"] = m.correct;
  d["false"] = m.false_associations;
  d["missed"] = m.missed;
  d["correct_rate"] = m.correct_rate;
  d["false_rate"] = m.false_rate;
  d["missed_rate"] = m.missed_rate;
  d["linked_tuples"] = m.linked_tuples;
  d["false_tuples"] = m.false_tuples;
  return d;
}

PyFused fuse(const PyAssociation& association, const std::string& rule, const std::string& ci_criterion,
             const py::object& common_process_noise, const py::object& correlation, double process_noise,
             const std::string& name, bool registration, const py::object& threads) {
  const ThreadLimit limit(threads);
  TrackFuserOptions o;
  o.rule = parse_enum<FusionRule>(rule, "fuse: rule");
  o.ci.criterion = parse_enum<CiCriterion>(ci_criterion, "fuse: ci_criterion");
  o.process_noise = process_noise;
  o.registration = registration;
  if (!common_process_noise.is_none()) o.common_process_noise = common_process_noise.cast<double>();
  if (!correlation.is_none()) o.correlation = correlation.cast<double>();
  if (o.rule != FusionRule::kBarShalomCampo && (!common_process_noise.is_none() || !correlation.is_none()))
    throw InputError("fuse: common_process_noise and correlation apply to rule='bsc' only");
  if (!common_process_noise.is_none() && !correlation.is_none())
    throw InputError("fuse: common_process_noise and correlation: give one cross-covariance, not both");
  // The engine fuses an association stored in a file: a copy of the input with this one stored.
  TrackFile file = *association.input;
  store_outcome(file, association.outcome);
  PyFused out;
  {
    py::gil_scoped_release release;
    const auto control = limit.apply();
    out.summary = fuse_track_file(file, association.outcome.record.name, name, o);
  }
  out.record = file.fused.back();
  out.input = std::make_shared<const TrackFile>(std::move(file));
  return out;
}

PyTrackFile read_file(const std::string& path) {
  TrackFile file;
  {
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> hdf5(hdf5_mutex());
    file = read_track_file(path);
  }
  return {std::make_shared<const TrackFile>(std::move(file)), path};
}

void write_file(const std::string& path, const py::object& tracks, const py::object& sensors,
                const std::vector<PyAssociation>& associations, const std::vector<PyFused>& fused) {
  TrackFile file = *track_file_of(tracks, sensors);
  for (const PyAssociation& a : associations) store_outcome(file, a.outcome);
  for (const PyFused& f : fused) {
    std::erase_if(file.fused, [&](const FusedTrackRecord& r) { return r.name == f.record.name; });
    file.fused.push_back(f.record);
  }
  py::gil_scoped_release release;
  const std::lock_guard<std::mutex> hdf5(hdf5_mutex());
  write_track_file(path, file);  // validates every section before it is written
}

py::object tracks_object(const py::object& tracks, const py::object& sensors) {
  return py::cast(PyTrackFile{track_file_of(tracks, sensors), kArraysSource});
}

}  // namespace

}  // namespace trackassoc::python

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  using namespace trackassoc::python;
  m.doc() = "trackassoc's C++ engine (the package trackassoc re-exports it; see help(trackassoc)).";
  py::register_exception<trackassoc::InputError>(m, "InputError", PyExc_ValueError);
  m.attr("__version__") = trackassoc::kVersion;
  bind_results(m);

  // The keyword options are listed from the one field table (associator_fields.hpp), so the
  // docstring names every key with its default and range, as option_help() and --options do.
  static const std::string associate_doc =
      R"(associate(tracks, sensors=None, threads=None, **options) -> Association

Associates the local tracks of every sensor (the engine's association interface, the same code
and results as `trackassoc associate`).

tracks   a TrackFile (read(path)), a dict of numpy arrays or a structured numpy array with the
         /tracks columns: sensor (N, int), track (N, int), t (N, float), state (N x 4: x, y, vx, vy,
         or N x 6: x, y, z, vx, vy, vz), cov (N x 10 | N x 21, the packed upper triangle row-major,
         or N x D x D), truth (N, int, optional, -1 = unknown). Checked as a file's /tracks is:
         ValueError (trackassoc.InputError) naming the column and row on a bad shape or dtype,
         NaN/inf, a covariance that is not symmetric positive definite, a duplicate (sensor, track, t).
sensors  None (every sensor id of tracks, period = the median report interval of its tracks), a
         list of ids, or a dict of /sensors columns (id; period, position, ... optional). Only
         with arrays.
threads  None (all cores) or the number of oneTBB workers; results are the same for any.
options  the `associate` flags as keywords (also trackassoc.option_help()). Unknown keys, wrong
         types and out-of-range values raise ValueError with the one-line message of --options:
)" + trackassoc::associator_option_fields().help(trackassoc::AssociatorOptions{}, "  ") +
      R"(
Returns an Association: tuples (K x S), sensor_ids, target, cost, unassociated, summary, and
to_pandas(). The GIL is released while the engine runs.)";
  m.def("associate", &associate, py::arg("tracks"), py::arg("sensors") = py::none(),
        py::arg("threads") = py::none(), associate_doc.c_str());
  m.def("evaluate", &evaluate, py::arg("association"), py::arg("tracks") = py::none(),
        R"(evaluate(association, tracks=None) -> dict

Scores an Association against the ground truth in /tracks/truth (as `trackassoc evaluate`), by
per-row truth: a local track (sensor, track; a recycled number split into its pieces) has as its
target the majority of its rows' truth; a target tracked by >= 2 sensors is correct when one output
group (the tuples sharing a target number) holds exactly its local tracks, false when one of its
tracks shares a group with another target's or a false track, missed otherwise. Returns
targets, correct, false, missed, correct_rate, false_rate, missed_rate, linked_tuples, false_tuples.
tracks: the TrackFile or arrays to score against (default: those associated).)");
  m.def("fuse", &fuse, py::arg("association"), py::arg("rule") = "naive", py::arg("ci_criterion") = "trace",
        py::arg("common_process_noise") = py::none(), py::arg("correlation") = py::none(),
        py::arg("process_noise") = 2.0, py::arg("name") = "", py::arg("registration") = true,
        py::arg("threads") = py::none(),
        R"(fuse(association, rule='naive', ci_criterion='trace', common_process_noise=None,
     correlation=None, process_noise=2.0, name='', registration=True, threads=None) -> Fused

Fuses the local tracks of each tuple into one track over time (as `trackassoc fuse`): rule 'naive'
(information-weighted, independent errors), 'bsc' (Bar-Shalom-Campo with the cross-covariance of
common_process_noise SIGMA or correlation RHO; without either, the scenario's tracker process noise)
or 'ci' (covariance intersection, omega minimising ci_criterion 'trace' or 'det'). process_noise:
the CV model's sigma [m/s^2] moving a report to a fused time. name: the /fused name (default: the
association's). registration: when the association's registration was applied, fuse the reports
corrected by it, as `trackassoc fuse` does (False: as recorded, its --no-registration). Returns a
Fused: arrays (tuple, t, state, cov, sources, truth, omega), summary, to_pandas().)");
  m.def("read", &read_file, py::arg("path"),
        R"(read(path) -> TrackFile

Reads and validates a schema v1 HDF5 file with the C++ reader (the command line's): tracks,
sensors, associations and fused groups as attributes. Raises ValueError naming the file, dataset
and row on malformed content.)");
  m.def("write", &write_file, py::arg("path"), py::arg("tracks"), py::arg("sensors") = py::none(),
        py::arg("associations") = std::vector<PyAssociation>{}, py::arg("fused") = std::vector<PyFused>{},
        R"(write(path, tracks, sensors=None, associations=(), fused=())

Writes a schema v1 HDF5 file atomically (PATH.tmp, then renamed): tracks (a TrackFile or arrays, as
associate takes them) with the given Association and Fused results stored under /associations and
/fused, replacing groups of the same name. The command line reads it back (trackassoc evaluate,
fuse, export csv).)");
  m.def("tracks", &tracks_object, py::arg("tracks"), py::arg("sensors") = py::none(),
        R"(tracks(tracks, sensors=None) -> TrackFile

The arrays (as associate takes them) validated once into a TrackFile, to associate several times
or write without converting again.)");
  m.def(
      "option_help",
      [] { return trackassoc::associator_option_fields().help(trackassoc::AssociatorOptions{}); },
      R"(option_help() -> str

The keyword options of associate(), one line each: key, default, range and what it does.)");
}
