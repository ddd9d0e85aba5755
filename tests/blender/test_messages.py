"""Native errors in the add-on's words (issue 29): a computation that could
not finish says what failed and what to change on the mesh, never blaming an
OpenCL device that was not involved; only a DeviceError is the device's fault
and points at the CPU backend. A ConstraintError speaks of the caller's
constraints: pinned UVs for Isometric Unwrap, the pins and pairs the native
text names for the morph."""
import bpy
import pytest

from paramorph import messages
from paramorph.native import native
from test_morph import morph_pair

pytestmark = pytest.mark.usefixtures("addon_scene")

FOLDS = "its map keeps folds where the model turns against its simplified proxy"
STALLED = ("mesh B: its pins and pairs cannot all be met on the model without folding its map "
           "(stalled 42% of the way, near pins 1, 3)")


def test_a_compute_error_says_what_failed_and_never_blames_the_device():
    text = messages.describe(native.ComputeError(FOLDS))
    assert FOLDS in text, text
    assert "OpenCL" not in text and "backend" not in text.lower() and "device" not in text, text
    assert "Clean Up" in text and "report the mesh" in text, text
    assert "turn on Repair" in messages.describe(native.ComputeError("x"), repair=False)
    assert "turn on Repair" not in messages.describe(native.ComputeError("x"), repair=True)


def test_a_device_error_blames_the_device_and_says_how_to_avoid_it():
    assert issubclass(native.DeviceError, native.ComputeError)
    text = messages.describe(native.DeviceError("building kernels/sphere.cl failed on PoCL / cpu"))
    assert text.startswith("the OpenCL device failed (building kernels/sphere.cl failed"), text
    assert "CPU backend" in text and "--backend cpu" in text, text


def test_constraint_errors_speak_of_the_callers_constraints():
    text = messages.describe(native.ConstraintError(STALLED), constraints="pins")
    assert "UV" not in text and "unpin" not in text, text
    assert STALLED in text and text.endswith("move or remove the pins or pairs it names"), text
    # Cut-and-paste's constraints are neither pins nor UVs: the native text alone.
    folded = "the feature map has 3 folded faces; the feature cannot be stored as a displacement map"
    assert messages.describe(native.ConstraintError(folded)) == folded
    uv = messages.describe(native.ConstraintError("2 faces stay folded"), constraints="uv")
    assert uv.startswith("the pinned UVs cannot all be met without folds (2 faces stay folded)"), uv


@pytest.mark.parametrize("error, expected, absent", [
    (native.ComputeError(FOLDS),
     f"Blob → Octopus: the computation could not finish ({FOLDS}): try Mesh > Clean Up", ("OpenCL", "backend")),
    (native.ConstraintError(STALLED),
     "Blob → Octopus: Octopus: its pins and pairs cannot all be met on the model without folding its map "
     "(stalled 42% of the way, near pins 1, 3) (A: Blob, B: Octopus): move or remove the pins or pairs it names",
     ("UV", "OpenCL")),
    (native.DeviceError("OpenCL error in clEnqueueNDRangeKernel (code -5)"),
     "Blob → Octopus: the OpenCL device failed (OpenCL error in clEnqueueNDRangeKernel (code -5)): "
     "choose the CPU backend", ("UV",)),
], ids=["compute", "constraint", "device"])
def test_morph_to_reports_what_failed_in_its_own_words(monkeypatch, error, expected, absent):
    source, target = morph_pair(source_subdivisions=2)

    def fails(*args, **kwargs):
        raise error
    monkeypatch.setattr(native, "morph", fails)
    objects_before = set(bpy.data.objects)
    with pytest.raises(RuntimeError) as raised:
        bpy.ops.paramorph.morph_to(topology="MERGED")
    text = str(raised.value)
    assert expected in text, text
    for word in absent:
        assert word not in text, text
    assert set(bpy.data.objects) == objects_before
