"""One rule for a progress callback's return value, whatever its type: None
(no return statement) or a true value goes on, a false value cancels (as
Python's `if` reads it); a value without a truth value is a typed error, and
the callback's own exception comes back as it was raised."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm

V, F = meshes.noisy_blob(2)


class Truthless:
    def __bool__(self):
        raise TypeError("no truth value")


@pytest.mark.parametrize("answer", [None, True, 1, 2.5, "yes", [0], np.bool_(True), object()],
                         ids=repr)
def test_none_and_true_values_go_on(answer):
    seen = []
    r = pm.sphere_map(V, F, progress=lambda fraction, stage: seen.append(fraction) or answer)
    assert r.flipped == 0 and seen and seen[-1] == 1.0


@pytest.mark.parametrize("answer", [False, 0, 0.0, "", [], np.bool_(False)], ids=repr)
def test_false_values_cancel(answer):
    with pytest.raises(pm.Cancelled):
        pm.sphere_map(V, F, progress=lambda fraction, stage: answer)


@pytest.mark.parametrize("answer", [np.array([True, False]), Truthless()], ids=["array", "truthless"])
def test_a_value_without_a_truth_value_is_a_typed_error(answer):
    with pytest.raises(pm.InvalidInputError, match="progress callback returned"):
        pm.sphere_map(V, F, progress=lambda fraction, stage: answer)


def test_the_callbacks_own_exception_comes_back_unchanged():
    class Mine(Exception):
        pass

    def callback(fraction, stage):
        raise Mine("from the callback")

    with pytest.raises(Mine, match="from the callback"):
        pm.sphere_map(V, F, progress=callback)
