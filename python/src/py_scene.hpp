#pragma once
// The Python scene objects of penalty._core, shared by the binding files: PyScene (a built scene
// and the Python callables run around its steps) and PyState (one of its MechanicalObjects).
#include "bindings.hpp"

#include "penalty/output/state_record.hpp"
#include "penalty/scene/scene.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace penalty::python {

/// A built scene plus the Python callables run around every step (SofaPython3 controllers).
struct PyScene {
    std::unique_ptr<scene::Scene> scene;
    std::vector<py::object> before_step;  ///< called with no argument before each step
    std::vector<py::object> after_step;   ///< called after each step

    void call_hooks(const std::vector<py::object>& hooks) {
        for (const py::object& hook : hooks) hook();
    }
    void step(std::int64_t n) {
        if (n < 0) throw py::value_error("step: n must be >= 0");
        for (std::int64_t k = 0; k < n; ++k) {
            call_hooks(before_step);
            scene->step();
            call_hooks(after_step);
        }
    }
};

/// A state record of a scene, found again by its label after the scene was built again from its
/// text (Scene::apply_pending_writes may replace the list of states when nodes are added or
/// removed after init). `->` and `*` give the current record.
class StateRecordRef {
public:
    StateRecordRef() = default;
    StateRecordRef(const py::object& scene, const output::StateRecord* record)
        : scene_(scene),
          label_(output::state_label(*record)),
          record_(record),
          generation_(scene.cast<const PyScene&>().scene->generation()) {}
    const output::StateRecord* operator->() const { return get(); }
    const output::StateRecord& operator*() const { return *get(); }

private:
    const output::StateRecord* get() const {
        const scene::Scene& s = *scene_.cast<const PyScene&>().scene;
        if (s.generation() == generation_) return record_;
        for (const output::StateRecord& r : s.states()) {
            if (output::state_label(r) != label_) continue;
            record_ = &r;
            generation_ = s.generation();
            return record_;
        }
        throw py::key_error("state '" + label_ + "' was removed from the scene");
    }
    py::object scene_;
    std::string label_;
    mutable const output::StateRecord* record_ = nullptr;
    mutable std::uint64_t generation_ = 0;
};

/// One MechanicalObject of a scene; `scene` keeps the owning Python scene alive.
struct PyState {
    py::object scene;
    StateRecordRef record;
};

}  // namespace penalty::python
