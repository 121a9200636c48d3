#pragma once
/// @file
/// A SOFA `.scn` file as a tree of nodes and components, with typed attribute readers and
/// SOFA's link resolution. No simulation object is built here: a scene builder maps this tree
/// onto the simulation API.
///
/// XML mapping: `<Node name=.. dt=.. gravity=..>` is a node; any other element is a component
/// whose type is the tag (`<Object type="T" .../>` is a component of type T, SOFA's older
/// syntax). The `name` and `template` attributes are stored in their own fields; every other
/// attribute is kept, in file order, with its line. Comments and text are ignored.
///
/// `<include href="Objects/X.xml" name=".." attr=".." Name__attr=".."/>` is expanded while
/// parsing, with SOFA's semantics (sofa::simulation::xml::includeNode): the included file's root
/// becomes a child of the including node (its components and child nodes are spliced into the
/// including node when that root is named `Group` or `_Group_`), `name` renames that root, and
/// every other attribute replaces the value of that attribute in every component of the
/// included tree that has it (only in components named `Name` for `Name__attr`); it never adds an
/// attribute and never changes a node's. So `dx`, `rx`, `scale`, `src`, `contactStiffness`, ...
/// act through the included components that carry them. The file is looked for in the
/// including file's folder, then the data folders (`data_dirs`, then PENALTY_DATA_PATH);
/// includes nest up to 16 levels, and a loop is an error naming the chain of files.
/// scene-format.md has the details.
///
/// Every error is a SceneError whose message names the file, the line, the component and,
/// when one attribute is at fault, the attribute:
/// `scene.scn:12: UniformMass 'mass': attribute 'totalMass': expected a number, found 'abc'`.

#include "penalty/core/types.hpp"
#include "penalty/io/error.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penalty::io {

/// One XML attribute, its raw text and the line where it starts.
struct SceneAttribute {
    std::string name;
    std::string value;
    int line = 0;
};

/// What nodes and components share: type (tag), name, attributes, location.
struct SceneElement {
    std::string type;                        ///< tag: "Node", "MechanicalObject", ...
    std::string name;                        ///< `name` attribute ("" when absent)
    std::vector<SceneAttribute> attributes;  ///< all other attributes, in file order
    int line = 0;                            ///< line of the opening tag
    std::string file;                        ///< the file it was read from: the scene file as given to the
                                             ///< parser, or the resolved path of an `<include>`d file
    /// "" for an element of the scene file itself; for one read from an included file,
    /// ` (included from a.xml:3, included from scene.scn:12)`, innermost include first (appended
    /// to error messages).
    std::string included_from;

    /// The attribute with that name, or nullptr.
    [[nodiscard]] const SceneAttribute* find(std::string_view attribute) const;
    [[nodiscard]] bool has(std::string_view attribute) const { return find(attribute) != nullptr; }
    /// `Type 'name'`, or `Type` when unnamed (used in error messages).
    [[nodiscard]] std::string describe() const;
};

struct SceneNode;

/// A component (an object in SOFA's words).
struct SceneComponent : SceneElement {
    std::string template_name;        ///< `template` attribute ("" when absent): "Vec3d", "Rigid3d", ...
    const SceneNode* node = nullptr;  ///< the node holding this component
    std::size_t index = 0;            ///< position among the node's components (for `@[-1]` links)
};

/// A node: its own attributes (dt, gravity, ...), child nodes and components in file order.
struct SceneNode : SceneElement {
    const SceneNode* parent = nullptr;                        ///< nullptr for the root
    std::vector<std::unique_ptr<SceneNode>> children;         ///< child nodes, file order
    std::vector<std::unique_ptr<SceneComponent>> components;  ///< components, file order

    /// Child node / component with that name (first one), or nullptr.
    [[nodiscard]] const SceneNode* child(std::string_view child_name) const;
    [[nodiscard]] const SceneComponent* component(std::string_view component_name) const;
    /// SOFA's path: "/" for the root, "/A/B" below (the root's name is not part of paths).
    [[nodiscard]] std::string path() const;
};

/// A parsed scene. The tree is owned through pointers, so that the parent/node back-pointers
/// stay valid when the SceneFile is moved.
struct SceneFile {
    std::filesystem::path path;       ///< the file parsed ("" for a string)
    std::unique_ptr<SceneNode> root;  ///< the root `<Node>`

    /// Folder of the scene file (for relative data file names); "." for a string.
    [[nodiscard]] std::filesystem::path directory() const;
};

/// Parses a `.scn` file, expanding its `<include>`s (looked for in the including file's folder,
/// then in `data_dirs`, then in PENALTY_DATA_PATH's folders).
/// @throws SceneError `file: cannot open file`, `file:line: XML error: ...`,
///         `file:line: root element must be <Node>, found <X>`, `<Object>` without `type`;
///         for an include, `file:line: <include>: ...` (no `href`, cannot find the file, include
///         loop `a.scn includes b.xml includes a.scn`, nested more than 16 deep), or an error
///         inside the included file followed by ` (included from file:line)`.
[[nodiscard]] SceneFile parse_scene_file(const std::filesystem::path& path,
                                         const std::vector<std::filesystem::path>& data_dirs = {});

/// Parses scene text; `file_label` is used as the file name in messages; included files are
/// looked for in `file_label`'s folder (the current folder for a bare name), then as above.
[[nodiscard]] SceneFile parse_scene_string(std::string_view xml, const std::string& file_label,
                                           const std::vector<std::filesystem::path>& data_dirs = {});

/// Calls f(component) for every component of the tree, depth first, a node's components
/// before its children.
template <class F>
void for_each_component(const SceneNode& node, F&& f) {
    for (const auto& c : node.components) f(*c);
    for (const auto& child : node.children) for_each_component(*child, f);
}

// ---------------------------------------------------------------------------------------------
// Typed attribute readers. The `_or` forms return `fallback` when the attribute is absent;
// the others return nullopt / empty. A present but malformed attribute, or a link (`@...`)
// where a value is expected, throws SceneError naming file, line, component and attribute.

/// Throws the SceneError `file:line: Component 'name': attribute 'attr': what`
/// (`line` is the attribute's line, or the element's when the attribute is absent).
[[noreturn]] void throw_attribute_error(const SceneElement& element, std::string_view attribute,
                                        const std::string& what);
/// Throws the SceneError `file:line: Component 'name': what`.
[[noreturn]] void throw_element_error(const SceneElement& element, const std::string& what);

/// Raw text of an attribute, or nullopt.
[[nodiscard]] std::optional<std::string> get_string(const SceneElement& e, std::string_view attr);
/// One finite number (`1e-5`, `-3`, `0.25`).
[[nodiscard]] std::optional<double> get_double(const SceneElement& e, std::string_view attr);
[[nodiscard]] double get_double_or(const SceneElement& e, std::string_view attr, double fallback);
/// One integer (no fraction, no exponent).
[[nodiscard]] std::optional<std::int64_t> get_int(const SceneElement& e, std::string_view attr);
[[nodiscard]] std::int64_t get_int_or(const SceneElement& e, std::string_view attr, std::int64_t fallback);
/// SOFA booleans: `0`, `1`, `true`, `false` (case-insensitive).
[[nodiscard]] std::optional<bool> get_bool(const SceneElement& e, std::string_view attr);
[[nodiscard]] bool get_bool_or(const SceneElement& e, std::string_view attr, bool fallback);
/// Any count of numbers separated by blanks ("" gives an empty list).
/// Largest number of values in one inline attribute (`position="..."`, `triangles="..."`):
/// 1,000,000 (333,333 points). Larger data belongs in a mesh file; the list is refused
/// before it is parsed.
inline constexpr std::size_t kMaxInlineValues = 1'000'000;

[[nodiscard]] std::vector<double> get_doubles(const SceneElement& e, std::string_view attr);
/// Exactly 3 numbers: `"0 -9.81 0"`.
[[nodiscard]] std::optional<Vec3> get_vec3(const SceneElement& e, std::string_view attr);
[[nodiscard]] Vec3 get_vec3_or(const SceneElement& e, std::string_view attr, const Vec3& fallback);
/// A multiple of 3 numbers: Vec3 positions.
[[nodiscard]] std::vector<Vec3> get_vec3_list(const SceneElement& e, std::string_view attr);
/// A multiple of 7 numbers: Rigid3 positions `x y z qx qy qz qw` (quaternion normalized).
[[nodiscard]] std::vector<RigidFrame> get_rigid_list(const SceneElement& e, std::string_view attr);
/// Non-negative integers (point indices).
[[nodiscard]] std::vector<PointId> get_indices(const SceneElement& e, std::string_view attr);
/// Index tuples of N points (`hexas="0 4 6 2 1 5 7 3"` with N = 8): a multiple of N indices.
template <std::size_t N>
[[nodiscard]] std::vector<std::array<PointId, N>> get_elements(const SceneElement& e, std::string_view attr) {
    const std::vector<PointId> flat = get_indices(e, attr);
    if (flat.size() % N != 0) {
        throw_attribute_error(
            e, attr, "expected a multiple of " + std::to_string(N) + " indices, found " + std::to_string(flat.size()));
    }
    std::vector<std::array<PointId, N>> out(flat.size() / N);
    for (std::size_t i = 0; i < flat.size(); ++i) out[i / N][i % N] = flat[i];
    return out;
}

// ---------------------------------------------------------------------------------------------
// Links

/// True when an attribute value is a link (`@...`).
[[nodiscard]] bool is_link(std::string_view value);

/// What a link points to: a node, or a component and optionally one of its data.
struct LinkTarget {
    const SceneNode* node = nullptr;            ///< set when the link names a node (`@..`, `@/A`)
    const SceneComponent* component = nullptr;  ///< set when the link names a component
    std::string data;                           ///< data name after the last '.', "" for object links
};

/// Resolves one link written in attribute `attr` of `from` (the attribute must hold exactly one
/// link), as SOFA does, relative to the component's node:
///  - `@name`: a child node or component of the node, else of its ancestors (first match);
///  - `@../name`, `@./name`, `@A/B/name`: path segments (`..` = parent; `.` = this node; a name =
///    child node, or component for the last segment); after `..`/`.` or a first segment, no
///    ancestor search;
///  - `@/A/B`: from the root;
///  - `@[-k]`: the component k places before `from` in its node (`@[0]` is `from` itself);
///  - `...name.data`: the data `data` of the target (`@../../loader.position`, `@[-1].listRadius`).
/// @throws SceneError `file:line: Component 'name': attribute 'attr': broken link '@...': why`
[[nodiscard]] LinkTarget resolve_link(const SceneComponent& from, std::string_view attr);

/// Resolves every blank-separated link of an attribute (`collisionModels="@a @b"`).
[[nodiscard]] std::vector<LinkTarget> resolve_links(const SceneComponent& from, std::string_view attr);

/// Resolves a link text (with or without the leading '@') from component `from`; `attr` only
/// names the attribute in error messages.
[[nodiscard]] LinkTarget resolve_link_text(const SceneComponent& from, std::string_view link, std::string_view attr);

}  // namespace penalty::io
