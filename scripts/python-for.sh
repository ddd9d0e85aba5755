# Sourced by scripts/build.sh and scripts/bpy-venv.sh: `python_for VERSION`
# prints an interpreter for CPython VERSION (e.g. 3.13); a path is passed through.
# Looks at pythonX.Y on PATH (one that runs: pyenv's shim for a version that is
# not selected does not), then pyenv's versions (the machine image has 3.13
# there), then Debian's /usr/bin/pythonX.Y (Debian 13: python3.13).
python_for() {
  local want=$1 candidate root
  local candidates
  if [[ $want == */* ]]; then
    [ -x "$want" ] && { echo "$want"; return 0; }
    echo "python_for: $want is not an executable" >&2; return 1
  fi
  candidates=("$(command -v "python$want" 2>/dev/null || true)")
  if command -v pyenv >/dev/null; then
    root=$(pyenv root)
    # Newest patch release first.
    candidates+=($(ls -d "$root"/versions/"$want".*/bin/"python$want" 2>/dev/null | sort -V -r))
  fi
  candidates+=("/usr/bin/python$want")
  for candidate in "${candidates[@]}"; do
    [ -n "$candidate" ] && [ -x "$candidate" ] && "$candidate" -c '' 2>/dev/null && { echo "$candidate"; return 0; }
  done
  echo "python_for: no CPython $want found (PATH, pyenv, /usr/bin); install it (Debian 13: python$want-dev) or pass a path" >&2
  return 1
}
