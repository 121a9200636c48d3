#pragma once
// SofaPython3's Python force fields and mappings, made for the scene builder
// (scene::ExternalComponents; python_components.cpp).
#include "bindings.hpp"

#include "penalty/scene/live_data.hpp"

namespace penalty::python {

/// Makes the force field or mapping whose methods are those of a Python object: `resolve(id)`
/// gives the object, `dispatch(object, method, *arrays)` calls its method as SofaPython3 does
/// (penalty.sofa_api's dispatcher).
class PythonComponents final : public scene::ExternalComponents {
public:
    PythonComponents(py::object dispatch, py::object resolve)
        : dispatch_(std::move(dispatch)), resolve_(std::move(resolve)) {}
    PythonComponents(const PythonComponents&) = delete;
    PythonComponents& operator=(const PythonComponents&) = delete;
    ~PythonComponents() override;
    std::unique_ptr<BaseForceField> force_field(std::int64_t id, BaseState& state) override;
    std::unique_ptr<BaseMapping> mapping(std::int64_t id, BaseState& from, BaseState& to) override;

private:
    py::object dispatch_;
    py::object resolve_;
};

}  // namespace penalty::python
