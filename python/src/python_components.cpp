// SofaPython3's Python components as ordinary force fields and mappings of the simulation: each
// method call goes to the Python object (with the GIL) through penalty.sofa_api's dispatcher,
// which wraps the numpy arrays in SofaPython3's Data objects and calls addForce, addDForce,
// addKToMatrix, apply, applyJ, applyJT as SofaPython3 does (Binding_ForceField.cpp,
// Binding_Mapping.cpp). The arrays view the solver's vectors (no copy) for Vec3d DOFs and Rigid3d
// derivatives; Rigid3d frames (padded in memory) are copied in and out.
#include "python_components.hpp"

#include "penalty/mechanics/mapping.hpp"

#include <pybind11/numpy.h>

#include <string>
#include <type_traits>

namespace penalty::python {

namespace {

/// (n, 3) or (n, 6) view of a vector of Vec3 or RigidDeriv (read-only when `writeable` is false).
template <class T>
py::array deriv_view(const T* data, std::size_t n, bool writeable) {
    static_assert(sizeof(T) % sizeof(double) == 0);
    constexpr py::ssize_t width = sizeof(T) / sizeof(double);
    py::array_t<double> a({py::ssize_t(n), width}, {py::ssize_t(sizeof(T)), py::ssize_t(sizeof(double))},
                          reinterpret_cast<const double*>(data), py::none());
    if (!writeable) a.attr("flags").attr("writeable") = false;
    return a;
}

py::array coord_array(std::span<const Vec3> x, bool writeable) { return deriv_view(x.data(), x.size(), writeable); }
py::array coord_array(std::span<Vec3> x, bool writeable) { return deriv_view(x.data(), x.size(), writeable); }

/// Rigid3d frames as a (n, 7) copy x y z qx qy qz qw.
py::array coord_array(std::span<const RigidFrame> x, bool /*writeable*/) {
    py::array_t<double> a({py::ssize_t(x.size()), py::ssize_t(7)});
    auto w = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < x.size(); ++i) {
        for (int k = 0; k < 3; ++k) w(py::ssize_t(i), k) = x[i].center[k];
        for (int k = 0; k < 4; ++k) w(py::ssize_t(i), 3 + k) = x[i].orientation.coeffs()[k];
    }
    return a;
}

/// Vec1d values as a (n, 1) view, as SofaPython3 presents a Vec1d state.
py::array coord_array(std::span<double> x, bool writeable) { return deriv_view(x.data(), x.size(), writeable); }
py::array deriv_array(std::span<double> v, bool w) { return deriv_view(v.data(), v.size(), w); }
py::array deriv_array(std::span<const double> v, bool) { return deriv_view(v.data(), v.size(), false); }

py::array deriv_array(std::span<Vec3> v, bool w) { return deriv_view(v.data(), v.size(), w); }
py::array deriv_array(std::span<const Vec3> v, bool) { return deriv_view(v.data(), v.size(), false); }
py::array deriv_array(std::span<RigidDeriv> v, bool w) { return deriv_view(v.data(), v.size(), w); }
py::array deriv_array(std::span<const RigidDeriv> v, bool) { return deriv_view(v.data(), v.size(), false); }

/// The Python object of a component (a weak reference: the script's tree owns it) and the
/// dispatcher that calls its methods.
class PythonTarget {
public:
    PythonTarget(py::object dispatch, const py::object& target) : dispatch_(std::move(dispatch)), target_(target) {}
    PythonTarget(const PythonTarget&) = delete;
    PythonTarget& operator=(const PythonTarget&) = delete;
    ~PythonTarget() {
        py::gil_scoped_acquire gil;
        dispatch_ = py::object();
        target_ = py::weakref();
    }
    template <class... Args>
    py::object call(const char* method, Args&&... args) const {
        py::object self = target_();
        if (self.is_none())
            throw std::runtime_error(std::string("the Python object of a component is gone (") + method + ")");
        return dispatch_(self, method, std::forward<Args>(args)...);
    }

private:
    py::object dispatch_;
    py::weakref target_;
};

template <class DataTypes>
class PythonForceField final : public ForceField<DataTypes> {
public:
    using Coord = typename DataTypes::Coord;
    using Deriv = typename DataTypes::Deriv;
    PythonForceField(MechanicalObject<DataTypes>& state, py::object dispatch, py::object target)
        : ForceField<DataTypes>(state), target_(std::move(dispatch), target) {}

    void add_force(std::span<Deriv> f, std::span<const Coord> x, std::span<const Deriv> v) override {
        py::gil_scoped_acquire gil;
        target_.call("addForce", deriv_array(f, true), coord_array(x, false), deriv_array(v, false));
    }
    void add_dforce(std::span<Deriv> df, std::span<const Deriv> dx, double k_factor, double b_factor) const override {
        py::gil_scoped_acquire gil;
        target_.call("addDForce", deriv_array(df, true), deriv_array(dx, false), k_factor, b_factor);
    }
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override {
        py::gil_scoped_acquire gil;
        const auto n = py::ssize_t(this->state_->num_dofs());
        // SofaPython3's ForceField_Trampoline::addKToMatrix: a (N, N) or (N, N, 1) matrix, or
        // (i, j, value) rows, added as they are (the Python method applies kFactor itself).
        const py::array k = target_.call("addKToMatrix", factor, n, py::ssize_t(DataTypes::kDerivSize));
        auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(k);
        if (a.ndim() == 3 && a.shape(2) == 1) a = a.reshape({a.shape(0), a.shape(1)});
        if (a.ndim() == 2 && a.shape(1) == 3 && !(a.shape(0) == 3 && n * DataTypes::kDerivSize == 3)) {
            auto r = a.unchecked<2>();
            for (py::ssize_t i = 0; i < r.shape(0); ++i)
                triplets.emplace_back(offset + Index(r(i, 0)), offset + Index(r(i, 1)), r(i, 2));
            return;
        }
        if (a.ndim() != 2) throw py::type_error("addKToMatrix: expected a 2-D matrix or (i, j, value) rows");
        auto r = a.unchecked<2>();
        for (py::ssize_t i = 0; i < r.shape(0); ++i)
            for (py::ssize_t j = 0; j < r.shape(1); ++j)
                if (r(i, j) != 0.0) triplets.emplace_back(offset + Index(i), offset + Index(j), r(i, j));
    }

private:
    PythonTarget target_;
};

template <class T>
T zero_deriv() {
    if constexpr (std::is_same_v<T, Vec3>) return Vec3::Zero();
    else return T{};
}

template <class In, class Out = Vec3Types>
class PythonMapping final : public Mapping<In, Out> {
public:
    using InCoord = typename In::Coord;
    using InDeriv = typename In::Deriv;
    using OutCoord = typename Out::Coord;
    using OutDeriv = typename Out::Deriv;
    PythonMapping(MechanicalObject<In>& from, MechanicalObject<Out>& to, py::object dispatch, py::object target)
        : Mapping<In, Out>(from, to), target_(std::move(dispatch), target) {}

    void apply(std::span<OutCoord> out, std::span<const InCoord> in) override {
        py::gil_scoped_acquire gil;
        target_.call("apply", coord_array(out, true), coord_array(in, false));
    }
    void apply_j(std::span<OutDeriv> out, std::span<const InDeriv> in) const override {
        py::gil_scoped_acquire gil;
        target_.call("applyJ", deriv_array(out, true), deriv_array(in, false));
    }
    void apply_jt(std::span<InDeriv> in, std::span<const OutDeriv> out) const override {
        py::gil_scoped_acquire gil;
        target_.call("applyJT", deriv_array(in, true), deriv_array(out, false));
    }
    /// J column by column: applyJ of each unit input derivative (a Python mapping has no J).
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override {
        const std::size_t n_in = this->in_->num_dofs(), n_out = this->out_->num_dofs();
        constexpr int kOut = Out::kDerivSize;
        std::vector<InDeriv> unit(n_in);
        std::vector<OutDeriv> column(n_out);
        for (std::size_t i = 0; i < n_in; ++i) {
            for (int k = 0; k < In::kDerivSize; ++k) {
                std::fill(unit.begin(), unit.end(), zero_deriv<InDeriv>());
                reinterpret_cast<double*>(&unit[i])[k] = 1.0;
                std::fill(column.begin(), column.end(), zero_deriv<OutDeriv>());
                apply_j(column, unit);
                for (std::size_t r = 0; r < n_out; ++r)
                    for (int a = 0; a < kOut; ++a) {
                        const double value = reinterpret_cast<const double*>(&column[r])[a];
                        if (value != 0.0)
                            t.emplace_back(row_offset + Index(kOut * r) + a, col_offset + Index(In::kDerivSize * i) + k,
                                           value);
                    }
            }
        }
    }
    [[nodiscard]] std::size_t output_size() const override { return this->out_->num_dofs(); }

private:
    PythonTarget target_;
};

}  // namespace

std::unique_ptr<BaseForceField> PythonComponents::force_field(std::int64_t id, BaseState& state) {
    py::gil_scoped_acquire gil;
    py::object target = resolve_(id);
    if (auto* v = dynamic_cast<Vec3Object*>(&state))
        return std::make_unique<PythonForceField<Vec3Types>>(*v, dispatch_, target);
    if (auto* r = dynamic_cast<Rigid3Object*>(&state))
        return std::make_unique<PythonForceField<Rigid3Types>>(*r, dispatch_, target);
    throw std::invalid_argument("a Python force field needs a Vec3d or Rigid3d state");
}

std::unique_ptr<BaseMapping> PythonComponents::mapping(std::int64_t id, BaseState& from, BaseState& to) {
    py::gil_scoped_acquire gil;
    py::object target = resolve_(id);
    if (auto* scalar = dynamic_cast<Vec1Object*>(&to)) {  // Mapping_Vec3d_Vec1d
        auto* v = dynamic_cast<Vec3Object*>(&from);
        if (v == nullptr)
            throw std::invalid_argument(
                "a Python mapping onto a Vec1d state needs a Vec3d input (Mapping_Vec3d_Vec1d)");
        return std::make_unique<PythonMapping<Vec3Types, Vec1Types>>(*v, *scalar, dispatch_, target);
    }
    auto* out = dynamic_cast<Vec3Object*>(&to);
    if (out == nullptr)
        throw std::invalid_argument(
            "a Python mapping's output must be a Vec3d or Vec1d state (Mapping_Vec3d_Vec3d, Mapping_Rigid3d_Vec3d, "
            "Mapping_Vec3d_Vec1d)");
    if (auto* v = dynamic_cast<Vec3Object*>(&from))
        return std::make_unique<PythonMapping<Vec3Types>>(*v, *out, dispatch_, target);
    if (auto* r = dynamic_cast<Rigid3Object*>(&from))
        return std::make_unique<PythonMapping<Rigid3Types>>(*r, *out, dispatch_, target);
    throw std::invalid_argument("a Python mapping's input must be a Vec3d or Rigid3d state");
}

PythonComponents::~PythonComponents() {
    py::gil_scoped_acquire gil;
    dispatch_ = py::object();
    resolve_ = py::object();
}

}  // namespace penalty::python
