// SOFA HEAD's own quirks of writes after init, reproduced by default (docs/python.md, "Writing a
// Data after init"; each with its switch in SofaQuirkFixes, docs/sofa-compatibility.md):
//   - uniform_mass_lazy_write: UniformMass's update callback runs after the next step's weight;
//   - mesh_spring_stiffness_write: MeshSpringForceField's `stiffness` / `damping` are
//     SpringForceField's per-spring lists after init.
#include "penalty/scene/scene.hpp"

#include "penalty/mechanics/external_loads.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "scene/live_edits.hpp"

#include <algorithm>
#include <optional>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace penalty::scene {

namespace {

UniformMass<Vec3Types>* as_vec3_uniform(BaseMass* m) { return dynamic_cast<UniformMass<Vec3Types>*>(m); }
UniformMass<Rigid3Types>* as_rigid_uniform(BaseMass* m) { return dynamic_cast<UniformMass<Rigid3Types>*>(m); }

/// The mass a UniformMass's weight uses now (its lagging value while one is pending).
std::optional<double> weight_mass(BaseMass* m) {
    if (auto* v = as_vec3_uniform(m)) return v->lagging_weight_mass().value_or(v->vertex_mass());
    if (auto* r = as_rigid_uniform(m)) return r->lagging_weight_mass().value_or(r->vertex_mass());
    return std::nullopt;
}

std::optional<double> lagging_of(BaseMass* m) {
    if (auto* v = as_vec3_uniform(m)) return v->lagging_weight_mass();
    if (auto* r = as_rigid_uniform(m)) return r->lagging_weight_mass();
    return std::nullopt;
}

void set_lagging(BaseMass* m, double value) {
    if (auto* v = as_vec3_uniform(m)) v->set_lagging_weight_mass(value);
    if (auto* r = as_rigid_uniform(m)) r->set_lagging_weight_mass(value);
}

}  // namespace

BaseMass* Scene::built_mass_of(const std::string& component) const {
    for (BaseMass* m : masses_)
        if (const io::SceneComponent* c = component_of(m); c != nullptr && component_path(*c) == component) return m;
    return nullptr;
}

bool Scene::write_uniform_mass_quirk(io::SceneElement& element, const DataOwner& owner, std::string_view name,
                                     std::string_view text, const std::string& what) {
    if (!owner.node && element.type == "UniformMass" && (name == "totalMass" || name == "vertexMass") &&
        !options_.sofa_quirk_fixes.fix_uniform_mass_lazy_write) {
        // UniformMass::initDefaultImpl: totalMass is the Data used when it was set at init
        // (m_isTotalMassUsed); the update callback recomputes the other Data from it.
        const bool total_used = element.has("totalMass");
        BaseMass* mass = built_mass_of(owner.path);
        if (mass == nullptr || !weight_mass(mass)) return false;
        if (name == "totalMass" && !total_used) return true;  // updateFromVertexMass: totalMass = vertexMass·n
        if (name == "vertexMass") {
            std::vector<double> v;
            try {
                v = written_numbers(text, what, /*nonnegative=*/true);
            } catch (const std::invalid_argument&) {
                return false;  // a Rigid3Mass text (mass volume [inertia]): as a fresh scene
            }
            if (!total_used) return false;  // the Data init used: as a fresh scene
            // the weight of the next step takes it; updateFromTotalMass then sets vertexMass back
            // to totalMass / n (the text keeps it: the builder lets totalMass win, as SOFA)
            set_lagging(mass, v.at(0));
            write_attribute(element, name, text);
            return true;
        }
        // totalMass with totalMass used: the mass matrix takes it at the next step (the rebuild),
        // the weight of that step keeps vertexMass's value (carried over by the rebuild)
        set_lagging(mass, *weight_mass(mass));
        return false;
    }
    return false;
}

bool Scene::write_spring_list_quirk(const io::SceneElement& element, const DataOwner& owner, std::string_view name,
                                    std::string_view text, const std::string& what) {
    if (!owner.node && element.type == "MeshSpringForceField" && (name == "stiffness" || name == "damping") &&
        !options_.sofa_quirk_fixes.fix_mesh_spring_stiffness_write) {
        live_->spring_lists[owner.path][std::string(name)] = written_numbers(text, what, /*nonnegative=*/true);
        live_->rebuild = true;  // the springs take it at the next step (carry_live_quirks)
        return true;
    }
    return false;
}

void Scene::note_box_roi_write(const io::SceneElement& element, const DataOwner& owner, std::string_view name) {
    if (owner.node || element.type != "BoxROI" || (name != "box" && name != "orientedBox") ||
        options_.sofa_quirk_fixes.fix_box_roi_write)
        return;
    BoxRoiWrite& w = live_->box_roi_writes[owner.path];
    if (name == "box") {
        w.box_as_written = true;  // roiInit's ordering of the corners does not run again
    } else if (!w.oriented_of_init) {
        // computeOrientedBoxes does not run again: the boxes of init stay the ones tested
        const io::SceneAttribute* init = element.find("orientedBox");
        w.oriented_of_init = init != nullptr ? init->value : std::string();
    }
}

void Scene::carry_live_quirks(Scene& fresh) const {
    // UniformMass: a weight still lagging behind a written mass stays so in the new build.
    for (BaseMass* old : masses_) {
        const std::optional<double> lagging = lagging_of(old);
        const io::SceneComponent* c = component_of(old);
        if (!lagging || c == nullptr) continue;
        if (BaseMass* now = fresh.built_mass_of(component_path(*c))) set_lagging(now, *lagging);
    }
    // ConstantForceField: one `forces` value spread over N indices stays N forces (SOFA's d_forces
    // after the update callbacks): written indices of another count make the component Invalid.
    for (const auto& [built, c] : fresh.built_from_) {
        if (c->type != "ConstantForceField") continue;
        const std::string path = component_path(*c);
        for (const auto& [old_built, old_c] : built_from_)
            if (old_c->type == "ConstantForceField" && component_path(*old_c) == path)
                // recorded as ConstantForceField* (build_constant_force_field)
                static_cast<ConstantForceField*>(const_cast<void*>(built))
                    ->take_callback_state(*static_cast<const ConstantForceField*>(old_built));
    }
    // MeshSpringForceField: spring i takes value i of a written list, the last one past its end
    // (SpringForceField::updateSpringsFromTopologyIndices); rest lengths and the other list stay
    // as MeshSpringForceField::init made them.
    if (live_->spring_lists.empty()) return;
    for (const auto& [built, c] : fresh.built_from_) {
        if (c->type != "MeshSpringForceField") continue;
        const auto lists = live_->spring_lists.find(component_path(*c));
        if (lists == live_->spring_lists.end()) continue;
        auto* ff = static_cast<SpringForceField*>(const_cast<void*>(built));  // recorded as a SpringForceField*
        std::vector<Spring> springs = ff->springs();
        const auto take = [&](const char* data, double Spring::*member) {
            const auto list = lists->second.find(data);
            if (list == lists->second.end()) return;
            const std::vector<double>& v = list->second;
            for (std::size_t i = 0; i < springs.size(); ++i) springs[i].*member = v[std::min(i, v.size() - 1)];
        };
        take("stiffness", &Spring::ks);
        take("damping", &Spring::kd);
        ff->clear_springs();
        for (const Spring& s : springs) ff->add_spring(s);
        ff->init();
    }
}

namespace {

/// Numbers as SOFA writes them (%.17g), space-separated.
std::string number_text(std::span<const double> values) {
    std::ostringstream text;
    text.precision(17);
    for (std::size_t i = 0; i < values.size(); ++i) text << (i ? " " : "") << values[i];
    return text.str();
}

/// Points as SOFA writes a Vec3 list: their coordinates, space-separated.
std::string vec3_text(const std::vector<Vec3>& points) {
    std::vector<double> values;
    values.reserve(3 * points.size());
    for (const Vec3& p : points) values.insert(values.end(), {p.x(), p.y(), p.z()});
    return number_text(values);
}

}  // namespace

std::optional<DataValue> Scene::constant_force_data(const io::SceneComponent& c, const DataField& f) const {
    // SOFA's Data as ConstantForceField's init and update callbacks leave them: `indices` every
    // point when none are given (init), `forces` and `totalForce` what the callbacks made of the
    // scene's values once they ran (the first addForce)
    const bool own_indices = f.name == "indices" && !c.has("indices");
    if (f.name != "forces" && f.name != "totalForce" && !own_indices) return std::nullopt;
    for (const auto& [built, component] : built_from_) {
        if (component != &c) continue;
        const auto* ff = static_cast<const ConstantForceField*>(built);  // recorded as ConstantForceField*
        if (f.name == "forces") return make_data_value(f, vec3_text(ff->forces_data()));
        if (f.name == "totalForce") {
            const Vec3 t = ff->total_force_data();
            return make_data_value(f, number_text(std::span<const double>(t.data(), 3)));
        }
        std::vector<double> indices(ff->indices().begin(), ff->indices().end());
        return make_data_value(f, number_text(indices));
    }
    return std::nullopt;
}

std::optional<DataValue> Scene::quirk_value(const io::SceneComponent& c, const DataField& f) const {
    if (c.type == "ConstantForceField") return constant_force_data(c, f);
    if (c.type == "MeshSpringForceField") {
        const auto lists = live_->spring_lists.find(component_path(c));
        if (lists == live_->spring_lists.end()) return std::nullopt;
        const auto list = lists->second.find(f.name);
        if (list == lists->second.end()) return std::nullopt;
        return make_data_value(f, number_text(list->second));
    }
    if (c.type == "UniformMass" && f.name == "vertexMass" && f.python_form == "float") {
        // SOFA's vertexMass Data holds the written or the old value until the update callback runs
        if (BaseMass* m = built_mass_of(component_path(c)))
            if (const std::optional<double> lagging = lagging_of(m))
                return make_data_value(f, number_text(std::span<const double>(&*lagging, 1)));
    }
    return std::nullopt;
}

}  // namespace penalty::scene
