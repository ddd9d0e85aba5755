"""What the released paramorph_native wheel asks of the system, and plain
words for a load that fails because the system (or Blender) is older.

The wheels' manylinux policy (scripts/release.sh tags them with WHEEL_POLICY,
Blender's own floor, and fails when a module needs more) fixes the oldest
GNU C library they load with; a system below it gets a traceback-like
"version `GLIBC_2.xx' not found" from the loader, which says nothing to an
artist. No bpy here: the message is built before anything else loads."""
import os
import re
import sys

WHEEL_POLICY = "manylinux_2_28_x86_64"
GLIBC_FLOOR = (2, 28)
PYTHONS = ((3, 11), (3, 13))  # Blender 4.2 to 5.0; 5.1 and later


def system_glibc():
    """(major, minor) of the running GNU C library, or None (not glibc)."""
    try:
        text = os.confstr("CS_GNU_LIBC_VERSION") or ""  # e.g. "glibc 2.36"
    except (ValueError, OSError, AttributeError):
        return None
    match = re.match(r"glibc (\d+)\.(\d+)", text)
    return (int(match[1]), int(match[2])) if match else None


def _version(pair):
    return ".".join(str(part) for part in pair)


def explain_load_failure(error_text, glibc=None, python=None):
    """A plain sentence for a failure the user can act on, or "" when the
    error is none of those. glibc/python default to the running ones."""
    glibc = system_glibc() if glibc is None else glibc
    python = tuple(sys.version_info[:2]) if python is None else python
    wanted = [tuple(int(x) for x in found) for found in re.findall(r"GLIBC_(\d+)\.(\d+)", error_text)]
    if wanted or (glibc is not None and glibc < GLIBC_FLOOR):
        need = max(wanted + [GLIBC_FLOOR])
        have = f"glibc {_version(glibc)}" if glibc else "an older one"
        return (f"This Linux system is too old for paramorph: it needs the GNU C library (glibc) "
                f"{_version(need)} or newer and has {have}, as Blender itself does. Linux distributions from "
                f"2019 on have it (Debian 10, Ubuntu 20.04, RHEL, Rocky and Alma 8, Fedora 29 and later); "
                f"update the system to use paramorph.")
    if "GLIBCXX_" in error_text or "CXXABI_" in error_text:
        return ("This Linux system's C++ runtime (libstdc++) is older than paramorph needs (that of GCC 11, "
                "as in Debian 12, Ubuntu 22.04 or RHEL 9 and later); update the system to use paramorph.")
    if python not in PYTHONS and ("cpython-" in error_text or "No module named" in error_text
                                  or "undefined symbol: Py" in error_text):
        return (f"paramorph's native module is built for Python {' and '.join(map(_version, PYTHONS))} "
                f"(Blender 4.2 to 5.0, and 5.1 on); this Blender runs Python {_version(python)}.")
    return ""
