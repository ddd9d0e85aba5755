"""How long a run will take, said before it starts (issue 20: a 97k-face
morph ran 16 minutes with no warning). Each operator has a rate, seconds at
100k input faces, scaled as faces^1.2 (the solvers are a little worse than
linear); the defaults were measured on the 2-core machine the benchmarks run
on (tests/bench/esc_latency.py's meshes), and every finished run moves its
operator's rate towards what it took, so later estimates follow the
artist's own machine."""
EXPONENT = 1.2
# Estimates at least this long are said before the run starts.
SAY_FROM_SECONDS = 20.0

_rates = {  # seconds at 100k faces (the sum over the inputs of one run)
    "Sphere Map": 3.0,
    "Segment Extremities": 5.0,
    "Detect Feature Regions": 0.6,
    "Rank Similar Shapes": 5.0,
    "Isometric Unwrap": 1.5,
    "Copy Feature": 0.5,
    "Preview Matches": 8.0,
    "Morph To": 20.0,
}


def estimate(label, faces):
    """Seconds a run of operator `label` on `faces` input faces should take, or
    None for an operator without a rate."""
    rate = _rates.get(label)
    return None if rate is None or faces <= 0 else rate * (faces / 1e5) ** EXPONENT


def learn(label, faces, seconds):
    """A finished run moves its operator's rate halfway (geometrically) to
    what it measured. Runs on small inputs or under a second say more about
    overheads and caches (a repeated Sphere Map or Rank reuses its maps) than
    rates, and are left out."""
    if faces >= 5_000 and seconds >= 1.0 and label in _rates:
        measured = seconds / (faces / 1e5) ** EXPONENT
        _rates[label] = (_rates[label] * measured) ** 0.5


def duration_words(seconds):
    """'about 10 s' / 'about 3 min' / 'about 1.5 h'."""
    if seconds < 60:
        return f"about {max(5, int(round(seconds / 5)) * 5)} s"
    if seconds < 90 * 60:
        return f"about {int(round(seconds / 60))} min"
    return f"about {seconds / 3600:.1f} h"


def notice(label, faces, large_faces):
    """The sentence said before a run, or '' for a short one."""
    seconds = estimate(label, faces)
    if faces < large_faces and (seconds is None or seconds < SAY_FROM_SECONDS):
        return ""
    length = (f"{duration_words(seconds)} (estimated from the face count)" if seconds is not None
              else "this can take minutes")
    return f"{label}: {faces:,} faces: {length}"
