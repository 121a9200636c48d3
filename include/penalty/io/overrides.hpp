#pragma once
/// @file
/// Attribute overrides on a parsed scene (`penalty run SCENE --set /Floor/tri.contactStiffness=200`,
/// `penalty.load_scene(path, overrides={...})`, the parameter sweeps of docs/sweeps.md).
///
/// An override is `PATH.attribute=value`. PATH is a SOFA path from the root node: `/` (or empty,
/// or the root node's own name, `/root`) is the root; `/A/B` is child node B of child node A; the
/// last segment may name a component of the node instead (`/Floor/FloorTri1`). The attribute is
/// everything after the last '.' before '='; the value is everything after the first '=' (it may
/// hold blanks: `/Cube/dofs.position=0 1 0`).
///
/// Overrides change the parsed tree only: the scene builder then reads the new text with every
/// check and message it has for a file. An attribute the file has is replaced in place (its line
/// stays the file's line, so a builder message points at the attribute being overridden); an
/// attribute the file lacks is added, if the caller's filter accepts it (the scene layer accepts
/// the attributes the builder reads for that type: a typo is an error, not an ignored note).

#include "penalty/io/scene_file.hpp"

#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace penalty::io {

/// One parsed override.
struct Override {
    std::string path;       ///< "/Floor/FloorTri1" ("/" for the root)
    std::string attribute;  ///< "contactStiffness"
    std::string value;      ///< "200"
    std::string text;       ///< the override as written (for messages)
};

/// A malformed override text (no '=', no '.attribute', a bad attribute name): a usage error
/// (the command line's exit code 2), unlike a path or attribute the scene does not have
/// (SceneError, exit code 1).
class OverrideSyntaxError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

/// Parses `PATH.attribute=value`.
/// @throws OverrideSyntaxError naming the text and what is wrong.
[[nodiscard]] Override parse_override(std::string_view text);

/// Whether an attribute absent from an element may be added (element, attribute name).
using AttributeFilter = std::function<bool(const SceneElement&, std::string_view)>;

/// Applies overrides in order (a later one wins).
/// @throws SceneError `file: --set '/X.a=1': no node or component '/X' (...)`, or
///         `file:line: Type 'name': --set '...': no attribute 'a' in the file, and penalty does not
///         read it for Type (it reads: ...)`; `name` cannot be overridden.
void apply_overrides(SceneFile& file, const std::vector<Override>& overrides, const AttributeFilter& may_add = {},
                     const std::function<std::string(const SceneElement&)>& known_attributes = {});

/// The element a path names (see the file comment), or nullptr; `why` explains a failure.
[[nodiscard]] SceneElement* find_element(SceneFile& file, std::string_view path, std::string* why = nullptr);

}  // namespace penalty::io
