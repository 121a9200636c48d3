#pragma once
/// @file
/// The component registry: every SOFA component type a scene may use, declared once, with the
/// attributes it reads (name, kind, default, unit, check), its family (which decides when the
/// builder builds it in its node and SOFA's one-per-node rule), and the function that builds it.
/// `penalty info --components` prints it; the scene check (validate()), the builder, the
/// "not read by penalty" notes and `--set` overrides all read it, and nothing else lists
/// component types or their attributes.
///
/// Adding a component: one ComponentSpec in the table of its family's file
/// (src/scene/builder/<family>.cpp), one build function next to it, tests. See
/// docs/architecture.md ("Adding a SOFA component").

#include "penalty/io/scene_file.hpp"

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penalty {
struct SofaQuirkFixes;  // penalty/collision/intersection.hpp
}  // namespace penalty

namespace penalty::scene {

class SceneBuilder;  // src/scene/builder/scene_builder.hpp
struct NodeBuild;    // the builder's record of one node

/// How penalty treats a component type.
enum class ComponentCategory {
    physics,  ///< changes the simulation; built by its ComponentSpec::build
    loader,   ///< reads a data file (mesh, spheres); loaded when a physics component links to it
    ignored,  ///< visual or editor only: accepted and ignored
};

/// What a component is in its node. The builder builds a node's components family by family in
/// SOFA's order (see ComponentFamily order in build_node, src/scene/builder/scene_builder.cpp).
enum class ComponentFamily {
    gravity,             ///< sets its node's gravity (before anything else of the node)
    topology,            ///< one per node
    topology_helper,     ///< topology modifiers and geometry algorithms: accepted, build nothing (static topologies)
    state,               ///< MechanicalObject: one per node
    mapping,             ///< one per node
    mass,                ///< one per node
    force_field,         ///< any number, file order
    constraint,          ///< projective constraints, any number, file order
    ode_solver,          ///< one per node
    linear_solver,       ///< one per node; read by the node's ODE solver
    solver_part,         ///< read by a solver: linear systems, ordering methods, Newton-Raphson solvers
    collision_model,     ///< any number, file order (SOFA's broad-phase order, depth first)
    animation_loop,      ///< one per node
    collision_pipeline,  ///< CollisionPipeline
    composite_pipeline,  ///< CompositeCollisionPipeline
    sub_pipeline,        ///< SubCollisionPipeline: read by its composite
    broad_phase,         ///< read by a pipeline
    narrow_phase,        ///< read by a pipeline
    intersection,        ///< intersection method: read by a pipeline
    contact_manager,     ///< CollisionResponse: read by a pipeline
    loader,              ///< mesh and sphere files
    visual,              ///< ignored
    engine,              ///< data engines (BoxROI): built in file order with masses, force fields, constraints
    data_engine,         ///< engines whose inputs are links or values (TransformEngine, MergePoints): built
                         ///< when a component first reads an output, as SOFA evaluates engines on demand,
                         ///< else with the engines
};

/// The kind of value an attribute holds (as written in a scene file).
enum class AttributeKind {
    boolean,  ///< 0, 1, true, false
    integer,
    real,
    vector3,   ///< 3 numbers
    numbers,   ///< any count of numbers
    indices,   ///< non-negative integers
    points,    ///< 3·n numbers, or a link to positions
    frames,    ///< 7·n numbers (Rigid3d: x y z qx qy qz qw)
    elements,  ///< index tuples (edges, triangles, ...)
    text,
    link,   ///< `@path`
    links,  ///< blank-separated links
};

/// A check applied to a numeric attribute whatever its value comes from.
enum class ValueCheck {
    none,
    nonnegative,  ///< ≥ 0, else "must be >= 0, found '...'"
    positive,     ///< > 0, else "must be > 0, found '...'"
};

/// One attribute a component reads.
struct AttributeSpec {
    std::string_view name;
    AttributeKind kind = AttributeKind::real;
    /// SOFA's default as written in a scene ("0.45", "1", "0 -9.81 0"); "" when there is none
    /// (absent means empty, or the attribute is required); a text in parentheses describes a
    /// default that depends on the scene ("(the topology's points)").
    std::string_view default_value;
    std::string_view unit;  ///< SI unit ("Pa", "N/m", "kg", "m", "s", "deg"); "" when none
    ValueCheck check = ValueCheck::none;
    std::string_view meaning;  ///< a few words, for `penalty info --components`
};

/// Builds one component into its node (throws io::SceneError naming it on bad input).
using BuildFunction = void (*)(SceneBuilder& builder, const io::SceneComponent& component, NodeBuild& node);

/// One supported component type.
struct ComponentSpec {
    std::string_view type;  ///< SOFA class name or alias (XML tag)
    ComponentFamily family = ComponentFamily::visual;
    std::string_view summary;  ///< one line
    /// Attributes read, in the order `penalty info --components` lists them; `shared_attributes`
    /// are those the component shares with its family (collision models, springs, ...).
    std::span<const AttributeSpec> attributes = {};
    std::span<const AttributeSpec> shared_attributes = {};
    /// Null for components another builds (a CGLinearSolver by its ODE solver, loaders on demand,
    /// pipeline parts by their pipeline) and for ignored ones.
    BuildFunction build = nullptr;
    /// SOFA's class when `type` is an older alias (FixedConstraint → FixedProjectiveConstraint):
    /// SOFA names unnamed components after the class.
    std::string_view sofa_class = {};
};

/// The category of a family.
[[nodiscard]] ComponentCategory category_of(ComponentFamily family);

/// Every supported type, by family (physics first, then loaders, then ignored).
[[nodiscard]] std::span<const ComponentSpec> component_registry();

/// The spec of a type; nullptr when unknown.
[[nodiscard]] const ComponentSpec* find_component(std::string_view type);

/// Category of a type; nullopt when unknown.
[[nodiscard]] std::optional<ComponentCategory> component_category(std::string_view type);

/// The spec of one attribute of a type (its own, then shared); nullptr when it reads none such.
[[nodiscard]] const AttributeSpec* find_attribute(const ComponentSpec& spec, std::string_view name);

/// The attributes every node reads (`dt`, `gravity`).
[[nodiscard]] std::span<const AttributeSpec> node_attributes();

/// Names of the attributes penalty reads for an element type ("Node" for nodes); empty for an
/// unknown type.
[[nodiscard]] std::vector<std::string> read_attributes(std::string_view type);

/// Attributes of `element` (file order) that penalty does not read. SOFA Data that never change
/// the numbers (printLog, tags, draw, ...) are accepted silently on every element.
[[nodiscard]] std::vector<std::string> unread_attributes(const io::SceneElement& element);

/// `penalty info --components`: every type with its summary and attributes (kind, default,
/// unit, check), by category and family; or one type's when `type` is not empty.
/// @throws io::SceneError for an unknown `type`.
[[nodiscard]] std::string describe_components(std::string_view type = {});

/// SOFA's renamed components (ObjectFactory::createObject with ComponentChange's
/// renamedComponents): a component written with its name of before a rename
/// (`LinearMovementConstraint`, `StiffSpringForceField` ...) becomes the component of the new
/// name when penalty knows that one and not the old; a note per renamed component is returned.
[[nodiscard]] std::vector<std::string> apply_sofa_renames(io::SceneFile& scene);

/// SOFA's parse of a Data link (`triangleList="@roi.triangleIndices"`) that names no component:
/// BaseData::setParent keeps the path, finds no parent, and the Data stays unset. penalty does the
/// same: such an attribute of a physics component is removed from the parsed scene before it is
/// built (as if not written), and a note per removal is returned. Object links (`@name` without a
/// Data) are left for validate(), which refuses a broken one.
[[nodiscard]] std::vector<std::string> detach_unresolved_data_links(io::SceneFile& scene);

/// SOFA's Data<T>::read of a one-number attribute ignores the text after the number
/// (`tolerance="10-3"` reads 10): each such value is replaced by its number and a note returned,
/// unless `fixes.fix_number_trailing_text` (then the builder refuses it as unreadable).
/// number_prefix_quirk.cpp.
[[nodiscard]] std::vector<std::string> read_number_prefixes(io::SceneFile& scene, const SofaQuirkFixes& fixes);

/// Result of validate().
struct SceneCheck {
    std::vector<const io::SceneComponent*> physics;  ///< physics components, depth-first order
    std::vector<const io::SceneComponent*> loaders;  ///< loaders used by physics components (through a link)
    std::vector<const io::SceneComponent*> ignored;  ///< visual-only components, visual mappings and
                                                     ///< loaders no physics component uses
    /// One line: `ignored N visual-only components: OglModel x4, RequiredPlugin x13, ...`
    /// (types sorted by name; a mapping to a visual model is listed as `Type (visual output)`,
    /// a loader used only by visual components as `Type (visual only)`).
    std::string summary;
};

/// Checks a parsed scene before it is built:
///  - every component type is in the registry;
///  - a mapping whose `output` links to an ignored component is visual-only;
///  - the links in any attribute of a physics component resolve;
///  - a loader is "used" when a physics component links to it.
/// @throws io::SceneError `file:line: unknown component 'Type' (not supported by penalty)` for
///         the first unknown type, or the broken-link error of io::resolve_link().
[[nodiscard]] SceneCheck validate(const io::SceneFile& scene);

}  // namespace penalty::scene
