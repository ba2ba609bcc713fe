"""A Stone Soup track-to-track associator backed by trackassoc (issue 32, docs/design.md §9).

A drop-in for Stone Soup's ``OneToOneTrackAssociator`` and ``TrackToTrackCounting``::

    from trackassoc.stonesoup import TrackToTrackAssociator
    associator = TrackToTrackAssociator()                 # trackassoc.associate's options as keywords
    association_set = associator.associate_tracks(tracks_a, tracks_b, tracks_c)   # any number of sets
    association_set, unassociated_a, unassociated_b, unassociated_c = associator.associate(
        tracks_a, tracks_b, tracks_c)

Each set is one sensor; each Stone Soup ``Track`` of ``GaussianState`` one local track. Unlike the
Stone Soup associators, tracks are compared at common times on a grid over the union of their
reports (each moved there from its nearest report, engine/pipeline/sparse_sd_pipeline.hpp), so
asynchronous sensors, which share no timestamp, are associated too; and all sets are solved at once
(an S-D assignment), not pairwise. The result is Stone Soup's own ``AssociationSet`` of
``TimeRangeAssociation``: one per target seen by two or more tracks, its ``objects`` those tracks
(a target followed by several tracks of one set after a track break holds all of them), its
``time_range`` the span where at least two of them report. The tracks in no association are
returned by ``associate`` and kept in ``last_unassociated`` (one set per track set, Stone Soup #1170).

State order: Stone Soup's constant-velocity convention, (x, vx, y, vy[, z, vz]); give
``position_mapping`` and ``velocity_mapping`` for another. Times: seconds from the earliest state.

Stone Soup is imported only when an associator is used, so ``import trackassoc`` works without it.
"""
import numpy as np

from . import _core

__all__ = ["TrackToTrackAssociator", "tracks_to_arrays"]


def _default_mapping(ndim):
    if ndim == 4:
        return (0, 2), (1, 3)
    if ndim == 6:
        return (0, 2, 4), (1, 3, 5)
    raise ValueError("trackassoc.stonesoup: a GaussianState of %d dimensions needs position_mapping and "
                     "velocity_mapping (2-D: 4 state rows, 3-D: 6)" % ndim)


def tracks_to_arrays(track_sets, position_mapping=None, velocity_mapping=None):
    """The /tracks columns (a dict of numpy arrays, as trackassoc.associate takes) of Stone Soup
    track sets: sensor = the set's index, track = the track's index in the set (in iteration
    order), t = seconds from the earliest timestamp. Returns (arrays, keys, epoch), keys[s][k] the
    Track of set s, number k."""
    keys = [list(tracks) for tracks in track_sets]
    states = [(s, k, st) for s, tracks in enumerate(keys) for k, track in enumerate(tracks) for st in track.states]
    if not states:
        raise ValueError("trackassoc.stonesoup: the track sets hold no states")
    ndim = np.asarray(states[0][2].state_vector).shape[0]
    if position_mapping is None or velocity_mapping is None:
        pos, vel = _default_mapping(ndim)
        position_mapping = pos if position_mapping is None else position_mapping
        velocity_mapping = vel if velocity_mapping is None else velocity_mapping
    order = list(position_mapping) + list(velocity_mapping)
    n = len(states)
    try:
        x = np.stack([np.asarray(st.state_vector, dtype=np.float64).reshape(-1) for _, _, st in states])
        p = np.stack([np.asarray(st.covar, dtype=np.float64) for _, _, st in states])
    except (AttributeError, ValueError) as e:
        raise ValueError("trackassoc.stonesoup: every state must be a GaussianState of one dimension "
                         "(state_vector and covar): %s" % e) from e
    stamps = [st.timestamp for _, _, st in states]
    if any(ts is None for ts in stamps):
        raise ValueError("trackassoc.stonesoup: a state without a timestamp")
    epoch = min(stamps)
    arrays = {
        "sensor": np.fromiter((s for s, _, _ in states), np.int32, n),
        "track": np.fromiter((k for _, k, _ in states), np.int32, n),
        "t": np.fromiter(((ts - epoch).total_seconds() for ts in stamps), np.float64, n),
        "state": x[:, order],
        "cov": p[:, order][:, :, order],
    }
    return arrays, keys, epoch


def _coexistence_range(tracks):
    """(start, end) where at least two of `tracks` hold states; the union of their spans if never."""
    spans = sorted((t.states[0].timestamp, t.states[-1].timestamp) for t in tracks)
    events = sorted([(a, 1) for a, _ in spans] + [(b, -1) for _, b in spans], key=lambda e: (e[0], -e[1]))
    alive, start, end = 0, None, None
    for when, step in events:
        alive += step
        if step > 0 and alive == 2 and start is None:
            start = when
        if step < 0 and alive == 1:
            end = when
    if start is None or end is None or end < start:
        return spans[0][0], max(b for _, b in spans)
    return start, end


class TrackToTrackAssociator:
    """Associates the tracks of any number of Stone Soup track sets with trackassoc's engine.

    Keyword options are those of trackassoc.associate (trackassoc.option_help()), e.g.
    gate=0.99, solver='lr+ls', common_period=..., plus threads= and the state mapping
    (position_mapping, velocity_mapping; default Stone Soup's (x, vx, y, vy[, z, vz])).
    ``sensors`` may give the /sensors columns of the sets (a dict with id = 0, 1, ... the set
    indices, and e.g. period); by default a set's period is the median interval between the
    reports of its tracks.
    """

    def __init__(self, position_mapping=None, velocity_mapping=None, threads=None, sensors=None, **options):
        self.position_mapping = position_mapping
        self.velocity_mapping = velocity_mapping
        self.threads = threads
        self.sensors = sensors
        self.options = options
        self.last_result = None        # the trackassoc.Association of the last call
        self.last_unassociated = None  # one set of Tracks per track set, of the last call

    def associate(self, *track_sets):
        """(AssociationSet, unassociated tracks of set 0, of set 1, ...), as Stone Soup's
        OneToOneAssociator.associate returns for two sets."""
        from stonesoup.types.association import AssociationSet, TimeRangeAssociation
        from stonesoup.types.time import TimeRange

        if len(track_sets) < 2:
            raise ValueError("trackassoc.stonesoup: expected at least two track sets, got %d" % len(track_sets))
        arrays, keys, _ = tracks_to_arrays(track_sets, self.position_mapping, self.velocity_mapping)
        sensors = self.sensors
        if sensors is None:
            sensors = list(range(len(track_sets)))  # every set a sensor, even one without tracks
        result = _core.associate(arrays, sensors=sensors, threads=self.threads, **self.options)
        self.last_result = result
        members = {}  # target -> its tracks
        for tup, target in zip(result.tuples, result.target):
            for c, k in enumerate(tup):
                if k >= 0:
                    members.setdefault(int(target), []).append(keys[int(result.sensor_ids[c])][int(k)])
        associations = set()
        for tracks in members.values():
            if len(tracks) < 2:
                continue
            start, end = _coexistence_range(tracks)
            associations.add(TimeRangeAssociation(set(tracks), time_range=TimeRange(start, end)))
        associated = {id(t) for tracks in members.values() if len(tracks) >= 2 for t in tracks}
        unassociated = tuple({t for t in keys[s] if id(t) not in associated} for s in range(len(keys)))
        self.last_unassociated = unassociated
        return (AssociationSet(associations),) + unassociated

    def associate_tracks(self, *track_sets):
        """Stone Soup's TrackToTrackAssociator interface: the AssociationSet of the sets (any
        number >= 2); the unassociated tracks are in ``last_unassociated``."""
        return self.associate(*track_sets)[0]
