// Typed exceptions shared by every entry point (DESIGN.md §3).
//
// Each class maps one-to-one to a Python exception in paramorph_native; all
// mesh problems derive from MeshError, itself a std::invalid_argument so C++
// callers can catch the whole family. Messages name the offending elements.
#pragma once

#include <exception>
#include <sstream>
#include <stdexcept>
#include <string>

namespace paramorph {

/// Base of every "this input mesh cannot be processed" error.
class MeshError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};
/// The mesh has boundary loops where a closed surface is required.
class NotClosedError : public MeshError { using MeshError::MeshError; };
/// The mesh is closed where an open surface (with a boundary) is required.
class NotOpenError : public MeshError { using MeshError::MeshError; };
/// The mesh is closed and connected but its genus is not zero.
class NotGenusZeroError : public MeshError { using MeshError::MeshError; };
/// The mesh has more than one connected component.
class DisconnectedError : public MeshError { using MeshError::MeshError; };
/// An edge has more than two faces, or a vertex's faces do not form one fan.
class NonManifoldError : public MeshError { using MeshError::MeshError; };
/// Faces with (near) zero area or repeated vertex indices.
class DegenerateFaceError : public MeshError { using MeshError::MeshError; };
/// Malformed arrays: NaN/inf, index out of range, wrong shape or dtype.
class InvalidInputError : public MeshError { using MeshError::MeshError; };
/// Hard constraints that cannot all be met (duplicate pins, unreachable pins).
class ConstraintError : public MeshError { using MeshError::MeshError; };

/// The target has no room for a pasted feature where it is placed: the
/// region it needs covers the whole target or is not a disc.
class TargetTooSmallError : public MeshError { using MeshError::MeshError; };
/// A face selection (cut-and-paste, thesis ch. 5) selects no face at all.
class EmptySelectionError : public MeshError { using MeshError::MeshError; };
/// A face selection takes every face of the mesh: nothing is left around it.
class WholeMeshSelectedError : public MeshError { using MeshError::MeshError; };
/// Selected faces that are not one edge-connected disc or annulus: the message
/// says "is not connected", "has N boundary loops" or "has handles".
class SelectionTopologyError : public MeshError { using MeshError::MeshError; };

/// Raised when the caller's progress callback asks to stop.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled by the progress callback") {}
};

/// A computation could not finish (did not converge, no valid map found); the
/// message says what failed. Device failures are its subclass DeviceError.
class ComputeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
/// An OpenCL device failed: a kernel that does not build (with the device's
/// build log), out of resources, a cl::Error mid-run, backend="opencl" with no
/// usable device. The C++ backend (backend="cpu") avoids it; callers may fall
/// back. A ComputeError, so `catch (const ComputeError&)` still catches it.
class DeviceError : public ComputeError {
 public:
  using ComputeError::ComputeError;
};

namespace detail {
template <typename... Parts>
std::string concat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}
}  // namespace detail

/// Runs fn(); a mesh error it raises is raised again with "mesh <name>: " in
/// front and the same type, so a caller of a two-mesh entry point (matching,
/// morphing) learns which input to fix.
template <typename Fn>
auto for_mesh(const char* name, Fn&& fn) {
  const auto prefixed = [name](const std::exception& e) {
    return std::string("mesh ") + name + ": " + e.what();
  };
  try {
    return fn();
  } catch (const NotClosedError& e) {
    throw NotClosedError(prefixed(e));
  } catch (const NotOpenError& e) {
    throw NotOpenError(prefixed(e));
  } catch (const NotGenusZeroError& e) {
    throw NotGenusZeroError(prefixed(e));
  } catch (const DisconnectedError& e) {
    throw DisconnectedError(prefixed(e));
  } catch (const NonManifoldError& e) {
    throw NonManifoldError(prefixed(e));
  } catch (const DegenerateFaceError& e) {
    throw DegenerateFaceError(prefixed(e));
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(prefixed(e));
  } catch (const ConstraintError& e) {
    throw ConstraintError(prefixed(e));
  } catch (const EmptySelectionError& e) {
    throw EmptySelectionError(prefixed(e));
  } catch (const WholeMeshSelectedError& e) {
    throw WholeMeshSelectedError(prefixed(e));
  } catch (const SelectionTopologyError& e) {
    throw SelectionTopologyError(prefixed(e));
  } catch (const TargetTooSmallError& e) {
    throw TargetTooSmallError(prefixed(e));
  } catch (const MeshError& e) {
    throw MeshError(prefixed(e));
  }
}

}  // namespace paramorph

/// Checked precondition: throws ExceptionType with the streamed message parts.
/// Debug builds append file and line so a failing check is easy to find.
#ifdef PARAMORPH_DEBUG_CHECKS
#define PM_REQUIRE(condition, ExceptionType, ...)                                        \
  do {                                                                                    \
    if (!(condition))                                                                     \
      throw ExceptionType(::paramorph::detail::concat(__VA_ARGS__, " [", __FILE__, ":", \
                                                      __LINE__, "]"));                    \
  } while (0)
#else
#define PM_REQUIRE(condition, ExceptionType, ...)                            \
  do {                                                                        \
    if (!(condition)) throw ExceptionType(::paramorph::detail::concat(__VA_ARGS__)); \
  } while (0)
#endif
