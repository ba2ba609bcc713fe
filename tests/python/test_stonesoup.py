"""trackassoc.stonesoup.TrackToTrackAssociator on Stone Soup Track objects (issue 32), beside Stone
Soup's own OneToOneTrackAssociator on the same tracks (bench/stonesoup_t2t.py builds both the
tracks and the peer, as `experiment recorded` runs it). Skips when the Stone Soup source is not at
../shared/peers/stonesoup-src (it is optional: import trackassoc works without it)."""
import importlib.util
import os
import warnings

import numpy as np
import pytest

import trackassoc
from conftest import SOURCE_DIR, STONESOUP_SRC

if not os.path.isdir(os.path.join(STONESOUP_SRC, "stonesoup")):
    pytest.skip("Stone Soup source not found at %s (optional)" % STONESOUP_SRC, allow_module_level=True)
os.environ.setdefault("STONESOUP_SRC", STONESOUP_SRC)


def load_bench(name):
    spec = importlib.util.spec_from_file_location(name, os.path.join(SOURCE_DIR, "bench", name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


bench = load_bench("stonesoup_t2t")
# key_tuples: an AssociationSet as the bench's K x S tuples (a second track of one sensor in an
# association, a segment, as a tuple of its own: scored conservatively), plus the singletons.
tuples_of = load_bench("python_stonesoup").key_tuples
ss = bench.import_stonesoup()  # puts Stone Soup on sys.path
from stonesoup.types.association import AssociationSet, TimeRangeAssociation  # noqa: E402

from trackassoc.stonesoup import TrackToTrackAssociator  # noqa: E402


def stonesoup_tracks(path):
    d = bench.load(path)
    tracks, times = bench.build_tracks(d, ss)
    sets = [[tracks[k] for k in sorted(tracks) if k[0] == c] for c in range(len(d["sensors"]))]
    return d, tracks, times, sets


def test_three_sets_sync_against_stonesoup(simulated):
    d, tracks, times, sets = stonesoup_tracks(simulated("recorded_sync"))
    ours = TrackToTrackAssociator()
    result, *unassociated = ours.associate(*sets)
    assert isinstance(result, AssociationSet)
    assert all(isinstance(a, TimeRangeAssociation) and len(a.objects) >= 2 for a in result.associations)
    # every track in exactly one association or unassociated in its own set
    in_assoc = [t for a in result.associations for t in a.objects]
    assert len(in_assoc) == len({id(t) for t in in_assoc})
    assoc_ids = {id(t) for t in in_assoc}
    for s, tracks_s in enumerate(sets):
        ids_s = {id(t) for t in tracks_s}
        assert ids_s == (assoc_ids & ids_s) | {id(t) for t in unassociated[s]}
        assert not ({id(t) for t in unassociated[s]} & assoc_ids)
    for a in result.associations:
        assert a.time_range.start <= a.time_range.end
    truth_of = bench.track_truths(d)
    mine = bench.score(tuples_of(result, tracks, len(sets)), truth_of)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        threshold = float(ss["chi2"].ppf(0.99, d["state"].shape[1]))
        peer, _, _ = bench.run_chained(tracks, times, len(sets), bench.make_one2one(ss, tracks, threshold, "first"))
    theirs = bench.score(peer, truth_of)
    assert mine["targets"] == theirs["targets"] > 0
    assert mine["correct_rate"] >= theirs["correct_rate"]
    assert mine["correct_rate"] >= 0.9
    # the same association as the module on the file (the tracks' times are shifted to the first state)
    module = trackassoc.evaluate(trackassoc.associate(trackassoc.read(simulated("recorded_sync"))))
    assert mine["correct_rate"] == pytest.approx(module["correct_rate"], abs=1.0 / mine["targets"])


def test_two_sets_is_a_drop_in_for_one_to_one(simulated):
    d, tracks, times, sets = stonesoup_tracks(simulated("recorded_sync"))
    ours = TrackToTrackAssociator().associate_tracks(sets[0], sets[1])
    assert isinstance(ours, AssociationSet) and len(ours.associations) > 0
    truth_of = bench.track_truths(d)
    key_of = {id(t): k for k, t in tracks.items()}
    for a in ours.associations:
        keys = sorted(key_of[id(t)] for t in a.objects)
        assert [k[0] for k in keys] == [0, 1]
    right = sum(len({truth_of[key_of[id(t)]] for t in a.objects}) == 1 for a in ours.associations)
    assert right / len(ours.associations) >= 0.9


def test_asynchronous_sets_are_associated(simulated):
    """recorded_3s: periods 3/4/5 s, almost no shared timestamp; Stone Soup's OneToOne links
    (nearly) nothing there, ours associates most targets."""
    d, tracks, times, sets = stonesoup_tracks(simulated("recorded_3s"))
    result = TrackToTrackAssociator().associate_tracks(*sets)
    mine = bench.score(tuples_of(result, tracks, len(sets)), bench.track_truths(d))
    assert mine["correct_rate"] >= 0.7, mine

