"""Add-on preferences: the compute backend and the OpenCL devices found."""
import bpy

from .native import load_error, native


def backend(context):
    """The backend the user chose ("auto" when the preferences are not there)."""
    addon = context.preferences.addons.get(__package__)
    return addon.preferences.backend if addon is not None else "auto"


class ParamorphPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    backend: bpy.props.EnumProperty(
        name="Backend",
        items=[("auto", "Automatic", "OpenCL on a GPU, else the CPU path (faster than OpenCL on a CPU)"),
               ("opencl", "OpenCL", "Always OpenCL (an error when no device works)"),
               ("cpu", "CPU", "Plain C++ with OpenMP")],
        default="auto")

    def draw(self, context):
        layout = self.layout
        if native is None:
            layout.label(text=load_error, icon="ERROR")
            return
        layout.prop(self, "backend")
        box = layout.box()
        box.label(text="OpenCL devices")
        devices = native.devices()
        if not devices:
            box.label(text="none found: the CPU backend is used", icon="INFO")
        for device in devices:
            text = f"{device['platform']}: {device['name']} ({device['type']}, OpenCL {device['version']})"
            if device["selected"]:
                text += "  [in use]"
            if not device["usable"]:
                text += f"  unusable: {device['reason']}"
            box.label(text=text, icon="CHECKMARK" if device["usable"] else "X")


classes = (ParamorphPreferences,)
