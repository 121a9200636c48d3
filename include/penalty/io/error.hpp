#pragma once
/// @file
/// Errors raised by the input layer. Every message names where the problem is, in the
/// compiler style `file:line: what`, so that a user can jump to it.

#include <stdexcept>
#include <string>

namespace penalty::io {

/// A data file (mesh, sphere list, scene) cannot be found, opened or parsed.
/// The message starts with the file path and, when known, the 1-based line number:
/// `path:line: what` (or `path: what` when the whole file is concerned).
class LoadError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A `.scn` scene is malformed: XML error, unknown physics component, malformed attribute,
/// broken link. The message is `file:line: Component 'name': attribute 'attr': what`
/// (the attribute part only when one attribute is at fault).
class SceneError : public LoadError {
public:
    using LoadError::LoadError;
};

}  // namespace penalty::io
