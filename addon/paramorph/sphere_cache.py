"""Recent sphere maps by geometry, so the operators that need one (Segment
Extremities, Rank Similar Shapes) reuse what Sphere Map just computed on the
same mesh instead of solving again. Keyed by a digest of the vertex and
triangle arrays and the weights; a few entries, oldest dropped first."""
import collections
import hashlib

_entries = collections.OrderedDict()
_capacity = 8


def key(V, F, weights="conformal"):
    digest = hashlib.sha1(V.tobytes())
    digest.update(F.tobytes())
    return (digest.hexdigest(), weights)


def get(cache_key):
    positions = _entries.get(cache_key)
    if positions is not None:
        _entries.move_to_end(cache_key)
    return positions


def put(cache_key, positions):
    _entries[cache_key] = positions
    _entries.move_to_end(cache_key)
    while len(_entries) > _capacity:
        _entries.popitem(last=False)


def clear():
    _entries.clear()
