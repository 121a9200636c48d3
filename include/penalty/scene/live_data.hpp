#pragma once
/// @file
/// The live Data of a built scene: SofaPython3's object model (docs/python.md, "The object
/// model"). Every Data SOFA declares for a component or a node can be read with its current value
/// and SOFA's type, and written after init with the effect SOFA gives the write. Scene's
/// data_fields(), data(), set_data() and reinit() (scene.hpp) are the API; this header holds
/// their types.
///
/// One mechanism for every component type:
///   - which Data a component has: the registry's AttributeSpecs (the attributes penalty reads,
///     with their kind, default and check) and the catalog of SOFA's own Data
///     (src/scene/sofa_data_catalog.tsv, written by scripts/sofa-data-catalog.py from SOFA
///     itself: name, SOFA's type, how SofaPython3 presents the value, default);
///   - a value: a write that waits for the component's reinit(), else the live value (states,
///     the node's context, engine and loader outputs), else the scene's text, else the default;
///   - a write: checked as the builder checks the attribute (its kind and ValueCheck), then
///     taken as SOFA's component takes it (LiveWrite, one table: src/scene/live_policy.cpp). A
///     state vector is written in place; another Data is written into the scene's text, and the
///     scene is built again from it before the next step while every state, the time and the
///     memory that views of the states point to are kept (Scene::apply_pending_writes).

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mapping.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace penalty::scene {

struct AttributeSpec;

/// When a write of a Data after init takes effect: SOFA's behaviour, which penalty reproduces.
enum class LiveWrite : std::uint8_t {
    state,      ///< a state vector (MechanicalObject position, velocity, ...): written in place
    next_step,  ///< SOFA's component takes it at the next step (it reads it every step, a Data
                ///< callback or an engine's update): the scene is re-initialised with it before
                ///< the next step
    reinit,     ///< SOFA reads it at init: kept, and used once the component is re-initialised
                ///< (its reinit(), its node's init())
    no_effect,  ///< drawing, logging or bookkeeping: kept, changes nothing simulated
    refused,    ///< SOFA never reads it again after init, or penalty does not simulate it: the
                ///< write raises an error saying so
    read_only,  ///< an output SOFA computes (BoxROI's indices, a loader's points): refused
};

/// "state", "next step", ...
[[nodiscard]] std::string_view live_write_name(LiveWrite live);

/// What a Data owner is: a component or a node, by SOFA path ("/" root node, "/A/B" node or
/// component B of node A).
struct DataOwner {
    std::string path;
    bool node = false;
};

/// One Data (or link) of a component or node.
struct DataField {
    std::string name;
    /// SOFA's value type (BaseData::getValueTypeString: "d", "vector<d>", "Vec3d", ...); "link"
    /// for a link; for an attribute SOFA's catalog lacks, a type made from the registry's kind.
    std::string sofa_type;
    /// How SofaPython3 presents the value: "float", "int", "str", "list", "link",
    /// "ndarray:<dtype>:<ndim>" (dtype float64, float32 or int32).
    std::string python_form;
    std::string default_text;  ///< SOFA's default, as SOFA writes it
    LiveWrite live = LiveWrite::refused;
    const AttributeSpec* spec = nullptr;  ///< the registry's attribute (penalty reads it), or null
    /// Why a write is refused (LiveWrite::refused, read_only), in words.
    std::string refusal;
};

/// Which vector of a state a Data is (DataValue::state_vector).
enum class StateVector : std::uint8_t { none, position, velocity, force, rest_position, external_force };

/// A Data's current value.
struct DataValue {
    std::string python_form;         ///< as DataField::python_form
    std::string text;                ///< as SOFA writes it (BaseData::getValueString)
    std::vector<double> numbers;     ///< numbers of a numeric form, row-major
    std::size_t columns = 0;         ///< values per row of a 2-D array (0: scalar or 1-D)
    std::vector<std::string> items;  ///< the items of a "list" form (tags, names, links)
    /// A state vector: the binding may view the state's memory instead of copying `numbers`.
    BaseState* state = nullptr;
    StateVector state_vector = StateVector::none;
};

/// The Data of a component type (or of a node when `node`), for its Vec3d or Rigid3d template:
/// SOFA's (its catalog) then those only penalty declares (the registry), each with its LiveWrite.
[[nodiscard]] const std::vector<DataField>& data_fields_of_type(std::string_view type, bool node, bool rigid);

/// Values per row of a 2-D Data (0: scalar or 1-D).
[[nodiscard]] std::size_t data_field_columns(const DataField& field);

/// The value of Data `field` written `text` (SOFA's text form), typed as the field's python_form.
[[nodiscard]] DataValue make_data_value(const DataField& field, std::string_view text);

/// One row of SOFA's catalog (src/scene/sofa_data_catalog.tsv).
struct CatalogEntry {
    std::string name;
    std::string sofa_type;
    std::string python_form;
    std::string default_text;
    bool link = false;
};

/// SOFA's Data and links of a type (the node's for "Node"), for the Vec3d or Rigid3d template
/// (a type without a Rigid3d version gives its Vec3d rows); empty when SOFA's catalog lacks the
/// type.
[[nodiscard]] const std::vector<CatalogEntry>& sofa_data_catalog(std::string_view type, bool rigid);

/// Values per row of a SOFA vector type ("vector<Vec3d>" 3, "vector<Edge>" 2, "vector<RigidCoord3d>"
/// 7, "BoundingBox" 3, ...); 0 when the type is not a vector of fixed-size rows.
[[nodiscard]] std::size_t sofa_type_columns(std::string_view sofa_type);

/// Components whose code is outside the library, built by the scene builder through this
/// interface (BuildOptions::external): SofaPython3's Python force fields and mappings, whose
/// methods are Python (python/src/python_components.cpp). `id` is the component's `pythonObject`
/// attribute.
class ExternalComponents {
public:
    virtual ~ExternalComponents() = default;
    /// A force field on `state` (a Vec3d or Rigid3d state).
    virtual std::unique_ptr<BaseForceField> force_field(std::int64_t id, BaseState& state) = 0;
    /// A mapping from `from` to `to`.
    virtual std::unique_ptr<BaseMapping> mapping(std::int64_t id, BaseState& from, BaseState& to) = 0;
};

}  // namespace penalty::scene
