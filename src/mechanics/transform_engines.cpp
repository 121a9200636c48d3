#include "penalty/mechanics/transform_engines.hpp"

#include "sofa_vector_ops.hpp"

#include "penalty/core/error.hpp"
#include "sofa_quaternion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>

namespace penalty {

namespace {

/// One step of TransformEngine's list (Scale, Rotation, Translation operations).
struct TransformStep {
    enum class Kind { scale, rotation, translation } kind;
    Vec3 vector = Vec3::Zero();  ///< scale factors or translation
    Quat rotation = Quat::Identity();
};

/// TransformEngine::doUpdate's list (at most scale, rotation, quaternion, translation): each
/// operation added at the back, or at the front when inverse, and configured with its inverse
/// (Scale 1/s, Rotation q.inverse(), Translation −t).
struct TransformSteps {
    std::array<TransformStep, 4> steps{};
    std::size_t count = 0;
    void add(const TransformStep& s) { steps[count++] = s; }
    [[nodiscard]] const TransformStep* begin() const { return steps.data(); }
    [[nodiscard]] const TransformStep* end() const { return steps.data() + count; }
};

TransformSteps transform_steps(const TransformEngineParameters& p) {
    TransformSteps steps;
    const bool inv = p.inverse;
    if (p.scale != Vec3::Ones())
        steps.add({TransformStep::Kind::scale,
                   inv ? Vec3(1.0 / p.scale[0], 1.0 / p.scale[1], 1.0 / p.scale[2]) : p.scale, Quat::Identity()});
    if (p.rotation_deg != Vec3::Zero()) {
        // createQuaterFromEuler(r * (R_PI / 180.0)): each angle times the one factor π/180
        constexpr double kDegree = std::numbers::pi / 180.0;
        const Quat q = sofa_quat::from_euler_zyx(
            Vec3(p.rotation_deg[0] * kDegree, p.rotation_deg[1] * kDegree, p.rotation_deg[2] * kDegree));
        steps.add({TransformStep::Kind::rotation, Vec3::Zero(), inv ? sofa_quat::inverse(q) : q});
    }
    const Quat& q = p.quaternion;
    if (!(q.x() == 0 && q.y() == 0 && q.z() == 0 && q.w() == 1))
        steps.add({TransformStep::Kind::rotation, Vec3::Zero(), inv ? sofa_quat::inverse(q) : q});
    if (p.translation != Vec3::Zero())
        steps.add({TransformStep::Kind::translation, inv ? Vec3(-p.translation) : p.translation, Quat::Identity()});
    if (inv) std::reverse(steps.steps.begin(), steps.steps.begin() + std::ptrdiff_t(steps.count));  // each at the front
    return steps;
}

Vec3 apply_step(const TransformStep& s, const Vec3& x) {
    switch (s.kind) {
        case TransformStep::Kind::scale:
            return {x[0] * s.vector[0], x[1] * s.vector[1], x[2] * s.vector[2]};
        case TransformStep::Kind::rotation:
            return sofa_quat::rotate(s.rotation, x);
        case TransformStep::Kind::translation:
            return {x[0] + s.vector[0], x[1] + s.vector[1], x[2] + s.vector[2]};
    }
    return x;
}

Vec3 component_product(const Vec3& a, const Vec3& b) { return {a[0] * b[0], a[1] * b[1], a[2] * b[2]}; }
using sofa_vec::plus;

}  // namespace

std::vector<Vec3> transform_engine(std::span<const Vec3> points, const TransformEngineParameters& p) {
    const TransformSteps steps = transform_steps(p);
    std::vector<Vec3> out(points.begin(), points.end());
    for (Vec3& x : out)
        for (const TransformStep& s : steps) x = apply_step(s, x);
    return out;
}

std::vector<Vec3> transform_position(std::span<const Vec3> points, const TransformPositionParameters& p) {
    using M = TransformPositionMethod;
    std::vector<Vec3> out(points.size(), Vec3::Zero());
    // TransformPosition::init: the normal divided by its norm unless its squared norm is within
    // 1e-10 of 1
    Vec3 normal = p.normal;
    const double n2 = normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2];
    if (std::abs(n2 - 1.0) > 1e-10) {
        const double norm = std::sqrt(n2);
        normal = Vec3(normal[0] / norm, normal[1] / norm, normal[2] / norm);
    }
    constexpr double kPi = std::numbers::pi;
    // createQuaterFromEuler(rotation * M_PI / 180.0): (angle·π)/180
    const Quat q = sofa_quat::from_euler_zyx(
        Vec3(p.rotation_deg[0] * kPi / 180.0, p.rotation_deg[1] * kPi / 180.0, p.rotation_deg[2] * kPi / 180.0));
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3& x = points[i];
        switch (p.method) {
            case M::project_on_plane: {
                const Vec3 d(p.origin[0] - x[0], p.origin[1] - x[1], p.origin[2] - x[2]);
                const double t = d[0] * normal[0] + d[1] * normal[1] + d[2] * normal[2];
                out[i] = plus(x, Vec3(normal[0] * t, normal[1] * t, normal[2] * t));
                break;
            }
            case M::translation:
                out[i] = plus(x, p.translation);
                break;
            case M::scale:
                out[i] = plus(p.origin, component_product(
                                            Vec3(x[0] - p.origin[0], x[1] - p.origin[1], x[2] - p.origin[2]), p.scale));
                break;
            case M::scale_translation:
                out[i] = plus(component_product(x, p.scale), p.translation);
                break;
            case M::rotation:
                out[i] = sofa_quat::rotate(q, x);
                break;
            case M::scale_rotation_translation:
                out[i] = plus(sofa_quat::rotate(q, component_product(x, p.scale)), p.translation);
                break;
            case M::affine: {
                // Mat4x4 · (x, 1), rows summed left to right; divided by w unless |w| <= 1e-10
                // (then SOFA leaves the output point as it was: zero)
                std::array<double, 4> c{};
                for (int r = 0; r < 4; ++r)
                    c[std::size_t(r)] =
                        p.matrix(r, 0) * x[0] + p.matrix(r, 1) * x[1] + p.matrix(r, 2) * x[2] + p.matrix(r, 3) * 1.0;
                if (std::abs(c[3]) > 1e-10) out[i] = Vec3(c[0] / c[3], c[1] / c[3], c[2] / c[3]);
                break;
            }
        }
    }
    for (const PointId i : p.fixed_indices) {
        if (i < 0 || std::size_t(i) >= points.size())
            throw_invalid_argument("TransformPosition: fixedIndices holds ", i, " but there are ", points.size(),
                                   " points");
        out[std::size_t(i)] = points[std::size_t(i)];
    }
    return out;
}

MergedPoints merge_points(std::span<const Vec3> x1, std::span<const Vec3> x2, std::vector<PointId> mapping) {
    MergedPoints out;
    if (mapping.empty()) {  // addition
        out.points.assign(x1.begin(), x1.end());
        out.points.insert(out.points.end(), x2.begin(), x2.end());
        for (std::size_t i = 0; i < x1.size(); ++i) out.indices1.push_back(PointId(i));
        for (std::size_t i = 0; i < x2.size(); ++i) out.indices2.push_back(PointId(x1.size() + i));
        return out;
    }
    if (mapping.size() > x2.size())
        throw_invalid_argument("MergePoints: mappingX2 has ", mapping.size(), " indices but position2 has ", x2.size(),
                               " points");
    out.points.assign(x1.begin(), x1.end());
    for (std::size_t i = 0; i < mapping.size(); ++i)
        if (mapping[i] >= 0 && std::size_t(mapping[i]) < out.points.size()) out.points[std::size_t(mapping[i])] = x2[i];
    std::sort(mapping.begin(), mapping.end());
    std::size_t j = 0;  // SOFA reads mapping[j] past its end once the mapping is used up; penalty stops
    for (std::size_t i = 0; i < out.points.size(); ++i) {
        if (j < mapping.size() && PointId(i) == mapping[j]) {
            out.indices2.push_back(PointId(i));
            ++j;
        } else {
            out.indices1.push_back(PointId(i));
        }
    }
    return out;
}

namespace {

/// The blank-separated words of a line (strtok on " ", as SOFA).
std::vector<std::string> words(const std::string& line) {
    std::vector<std::string> out;
    std::istringstream in(line);
    for (std::string w; std::getline(in, w, ' ');)
        if (!w.empty()) out.push_back(w);
    return out;
}

double number(const std::string& word, const std::filesystem::path& path, int line) {
    char* end = nullptr;
    const double v = std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end != '\0' || !std::isfinite(v))
        throw_invalid_argument(path.string(), ":", line, ": expected a number, found '", word, "'");
    return v;
}

}  // namespace

Eigen::Matrix4d read_affine_transform_file(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw_invalid_argument(path.string(), ": cannot open the file");
    const std::string ext = path.extension().string();
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    std::string line;
    int line_number = 0;
    if (ext == ".tfm") {
        while (std::getline(in, line)) {
            ++line_number;
            if (line.find("Parameters") == std::string::npos) continue;
            std::vector<double> values;
            for (const std::string& w : words(line))
                if (w.find_first_of("1234567890.-") != std::string::npos)
                    values.push_back(number(w, path, line_number));
            if (values.size() != 12)
                throw_invalid_argument(path.string(), ":", line_number, ": expected 12 numbers, found ", values.size());
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) m(i, j) = values[3 * std::size_t(i) + std::size_t(j)];
                m(i, 3) = values[values.size() - 1 - std::size_t(i)];  // SOFA reads the translation backwards
            }
            return m;
        }
        throw_invalid_argument(path.string(), ": no line holds \"Parameters\"");
    }
    const bool trm = ext == ".trm";
    if (!trm && ext != ".txt" && ext != ".xfm")
        throw_invalid_argument(path.string(), ": unknown extension (TransformPosition reads .tfm, .trm, .xfm, .txt)");
    const std::size_t per_line = trm ? 3 : 4;
    int rows = 0;
    while (std::getline(in, line)) {
        ++line_number;
        if (line.empty()) continue;
        const std::vector<std::string> w = words(line);
        if (w.size() != per_line)
            throw_invalid_argument(path.string(), ":", line_number, ": expected ", per_line, " numbers, found ",
                                   w.size());
        if (rows == 4) throw_invalid_argument(path.string(), ":", line_number, ": more than 4 lines");
        for (std::size_t i = 0; i < per_line; ++i) {
            const double v = number(w[i], path, line_number);
            if (!trm) m(rows, Eigen::Index(i)) = v;
            else if (rows == 0) m(Eigen::Index(i), 3) = v;  // the translation line
            else m(rows - 1, Eigen::Index(i)) = v;
        }
        ++rows;
    }
    if (rows == 0) throw_invalid_argument(path.string(), ": no numbers");
    return m;  // rows not given stay the identity's, as SOFA
}

}  // namespace penalty
