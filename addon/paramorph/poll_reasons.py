"""Why an operator is greyed out, in the words Blender shows on its tooltip
(issue 20): each poll says what to do first through poll_message_set (Blender
3.0+); on older versions the check is the same, silently."""


def refuse(cls, reason):
    """False, with `reason` set as the greyed button's explanation."""
    if hasattr(cls, "poll_message_set"):
        cls.poll_message_set(reason)
    return False


def one_mesh(cls, context, modes=None):
    """The active object is a mesh (in one of `modes`, e.g. {"EDIT"}, when given)."""
    obj = context.active_object
    if obj is None or obj.type != "MESH":
        return refuse(cls, "Select a mesh object first (click it in the viewport)")
    if modes is not None and obj.mode not in modes:
        where = " or ".join(sorted(m.title() for m in modes))
        return refuse(cls, f"Works in {where} Mode: press Tab to switch")
    return True


def two_meshes(cls, context):
    """Two mesh objects selected: the source, then the target (active)."""
    target = context.active_object
    selected = context.selected_objects
    if len(selected) != 2 or target is None or target not in selected:
        return refuse(cls, f"Select two mesh objects: click the source, then Shift+click the target "
                           f"({len(selected)} selected now)")
    if any(o.type != "MESH" for o in selected):
        return refuse(cls, "Both selected objects must be meshes")
    return True
