#pragma once
// The error hierarchy of cgamesh. Every error the library throws derives from Error, so a
// caller can catch one type; the CLI maps each kind to its exit code and pybind11 to Python.

#include <stdexcept>
#include <string>

namespace cgamesh {

/// Base of every error cgamesh throws.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An argument or input file is unusable: NaN, a degenerate plane, a non-point, a corrupt file.
class InvalidInputError : public Error {
 public:
  using Error::Error;
};

/// An input file cannot be read or does not hold a valid model (missing, truncated, corrupt).
class FileError : public InvalidInputError {
 public:
  using InvalidInputError::InvalidInputError;
};

/// An output file could not be written: missing directory, no permission, disk full, the
/// target is a directory, ...
class WriteError : public Error {
 public:
  using Error::Error;
};

/// The mesh's connectivity does not allow the operation (non-manifold edge, open cut, ...).
class TopologyError : public Error {
 public:
  using Error::Error;
};

/// A numerical method failed: a singular system, no convergence.
class SolverError : public Error {
 public:
  using Error::Error;
};

/// The machine cannot provide what was asked: no EGL display or OpenGL 3.3 context for
/// rendering, no window system for the viewer.
class PlatformError : public Error {
 public:
  using Error::Error;
};

/// Inside a catch block: throws the error being handled again, as the same kind of cgamesh
/// error with `context` put before its message (e.g. "script.txt:4: "); other exceptions are
/// thrown again unchanged.
[[noreturn]] inline void rethrow_with_context(const std::string& context) {
  try {
    throw;
  } catch (const FileError& e) {
    throw FileError(context + e.what());
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(context + e.what());
  } catch (const WriteError& e) {
    throw WriteError(context + e.what());
  } catch (const TopologyError& e) {
    throw TopologyError(context + e.what());
  } catch (const SolverError& e) {
    throw SolverError(context + e.what());
  } catch (const PlatformError& e) {
    throw PlatformError(context + e.what());
  } catch (const Error& e) {
    throw Error(context + e.what());
  }
}

}  // namespace cgamesh
