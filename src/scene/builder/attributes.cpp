// The attribute reader of the family build functions (scene_builder.hpp: Attributes), and the
// naming helpers they share.
#include "scene/builder/scene_builder.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace penalty::scene {

using io::SceneComponent;

// ---- attribute reader -------------------------------------------------------------------------

Attributes::Attributes(const SceneComponent& component)
    : component_(component), spec_([&]() -> const ComponentSpec& {
          const ComponentSpec* spec = find_component(component.type);
          if (spec == nullptr) throw std::logic_error("penalty: no ComponentSpec for " + component.type);
          return *spec;
      }()) {}

const AttributeSpec& Attributes::declared(std::string_view name) const {
    if (const AttributeSpec* a = find_attribute(spec_, name)) return *a;
    throw std::logic_error("penalty: the builder of " + component_.type + " reads attribute '" + std::string(name) +
                           "', which its ComponentSpec does not declare");
}

void Attributes::check(const AttributeSpec& spec, double value) const {
    // the attribute as written; a link, with the value it led to (shortest round-trip text)
    const auto found = [&] {
        std::string text = io::get_string(component_, spec.name).value_or("");
        if (text.empty() || text.front() != '@') return text;
        std::array<char, 32> digits{};
        const auto end = std::to_chars(digits.data(), digits.data() + digits.size(), value).ptr;
        return std::string(digits.data(), end) + "' through '" + text;
    };
    if (spec.check == ValueCheck::nonnegative && value < 0)
        io::throw_attribute_error(component_, spec.name, "must be >= 0, found '" + found() + "'");
    if (spec.check == ValueCheck::positive && !(value > 0))
        io::throw_attribute_error(component_, spec.name, "must be > 0, found '" + found() + "'");
}

namespace {
/// A default written in a spec, as a number (a spec's text, so a malformed one is a penalty bug).
double parse_default_number(const AttributeSpec& a) {
    const std::string text(a.default_value);
    std::size_t used = 0;
    double v = 0.0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size())
        throw std::logic_error("penalty: attribute '" + std::string(a.name) + "' has no numeric default");
    return v;
}
Vec3 parse_default_vector(const AttributeSpec& a) {
    std::istringstream in{std::string(a.default_value)};
    Vec3 v;
    if (!(in >> v.x() >> v.y() >> v.z()))
        throw std::logic_error("penalty: attribute '" + std::string(a.name) + "' has no 3-number default");
    return v;
}
}  // namespace

bool Attributes::has(std::string_view name) const { return component_.has(declared(name).name); }

std::optional<io::SceneComponent> Attributes::linked_value(std::string_view name) const {
    const AttributeSpec& spec = declared(name);
    const io::SceneAttribute* own = component_.find(spec.name);
    if (own == nullptr || !io::is_link(own->value)) return std::nullopt;
    // SOFA's Data link (`translation="@loader.translation"`): the value of the linked Data, as
    // written on its component (following further links), else that component's default
    const io::SceneComponent* from = &component_;
    std::string attribute(spec.name);
    for (int depth = 0; depth < 16; ++depth) {
        const io::LinkTarget t = io::resolve_link(*from, attribute);
        if (t.component == nullptr || t.data.empty())
            fail(name, "a link to a value must name a component's Data (@component.data), found '" + own->value + "'");
        const io::SceneAttribute* target = t.component->find(t.data);
        if (target != nullptr && io::is_link(target->value)) {
            from = t.component;
            attribute = t.data;
            continue;
        }
        std::string text;
        if (target != nullptr) {
            text = target->value;
        } else {
            const ComponentSpec* target_spec = find_component(t.component->type);
            const AttributeSpec* data = target_spec != nullptr ? find_attribute(*target_spec, t.data) : nullptr;
            if (data == nullptr || data->default_value.empty() || data->default_value.front() == '(')
                fail(name, "links to Data '" + t.data + "' of " + t.component->describe() +
                               ", which the scene does not give and penalty does not compute there");
            text = std::string(data->default_value);
        }
        io::SceneComponent copy = component_;  // the same file, line and names in any error
        for (io::SceneAttribute& a : copy.attributes)
            if (a.name == spec.name) a.value = text;
        return copy;
    }
    fail(name, "a chain of more than 16 links");
}

const io::SceneComponent& Attributes::value_source(std::string_view name,
                                                   std::optional<io::SceneComponent>& storage) const {
    storage = linked_value(name);
    return storage ? *storage : component_;
}

double Attributes::real(std::string_view name) const {
    const AttributeSpec& a = declared(name);
    return real_or(name, parse_default_number(a));
}
double Attributes::real_or(std::string_view name, double fallback) const {
    const AttributeSpec& a = declared(name);
    std::optional<io::SceneComponent> linked;
    const double v = io::get_double_or(value_source(name, linked), a.name, fallback);
    check(a, v);
    return v;
}
std::optional<double> Attributes::optional_real(std::string_view name) const {
    const AttributeSpec& a = declared(name);
    std::optional<io::SceneComponent> linked;
    const std::optional<double> v = io::get_double(value_source(name, linked), a.name);
    if (v) check(a, *v);
    return v;
}
std::int64_t Attributes::integer(std::string_view name) const {
    return integer_or(name, std::int64_t(parse_default_number(declared(name))));
}
std::int64_t Attributes::integer_or(std::string_view name, std::int64_t fallback) const {
    const AttributeSpec& a = declared(name);
    std::optional<io::SceneComponent> linked;
    const std::int64_t v = io::get_int_or(value_source(name, linked), a.name, fallback);
    check(a, double(v));
    return v;
}
bool Attributes::boolean(std::string_view name) const {
    return boolean_or(name, parse_default_number(declared(name)) != 0.0);
}
bool Attributes::boolean_or(std::string_view name, bool fallback) const {
    std::optional<io::SceneComponent> linked;
    return io::get_bool_or(value_source(name, linked), declared(name).name, fallback);
}
Vec3 Attributes::vector3(std::string_view name) const { return vector3_or(name, parse_default_vector(declared(name))); }
Vec3 Attributes::vector3_or(std::string_view name, const Vec3& fallback) const {
    std::optional<io::SceneComponent> linked;
    return io::get_vec3_or(value_source(name, linked), declared(name).name, fallback);
}
std::optional<Vec3> Attributes::optional_vector3(std::string_view name) const {
    std::optional<io::SceneComponent> linked;
    return io::get_vec3(value_source(name, linked), declared(name).name);
}
std::string Attributes::text(std::string_view name) const {
    const AttributeSpec& a = declared(name);
    return io::get_string(component_, a.name).value_or(std::string(a.default_value));
}
std::optional<std::string> Attributes::optional_text(std::string_view name) const {
    return io::get_string(component_, declared(name).name);
}
std::vector<double> Attributes::numbers(std::string_view name) const {
    std::optional<io::SceneComponent> linked;
    return io::get_doubles(value_source(name, linked), declared(name).name);
}
std::vector<int> Attributes::as_ints(std::string_view name, const std::vector<double>& values) const {
    std::vector<int> out;
    out.reserve(values.size());
    for (const double v : values) {
        if (!(v >= double(std::numeric_limits<int>::min()) && v <= double(std::numeric_limits<int>::max())) ||
            v != std::floor(v))
            fail(name, "expected integers from " + std::to_string(std::numeric_limits<int>::min()) + " to " +
                           std::to_string(std::numeric_limits<int>::max()) + ", found " + num(v));
        out.push_back(static_cast<int>(v));
    }
    return out;
}
std::vector<PointId> Attributes::indices(std::string_view name) const {
    return io::get_indices(component_, declared(name).name);
}
std::vector<Vec3> Attributes::points(std::string_view name) const {
    return io::get_vec3_list(component_, declared(name).name);
}
std::vector<RigidFrame> Attributes::frames(std::string_view name) const {
    return io::get_rigid_list(component_, declared(name).name);
}
io::LinkTarget Attributes::link(std::string_view name) const {
    return io::resolve_link(component_, declared(name).name);
}
std::vector<io::LinkTarget> Attributes::links(std::string_view name) const {
    return io::resolve_links(component_, declared(name).name);
}
bool Attributes::is_link(std::string_view name) const {
    const io::SceneAttribute* a = component_.find(declared(name).name);
    return a != nullptr && io::is_link(a->value);
}
void Attributes::fail(std::string_view name, const std::string& what) const {
    io::throw_attribute_error(component_, declared(name).name, what);
}

// ---- helpers ----------------------------------------------------------------------------------

/// SOFA's name for an unnamed component of the XML loader (ObjectElement::initNode →
/// ComponentNameHelper::resolveName, xml convention): its class name followed by a counter of the
/// unnamed components of that class created so far in the same node (context), from 1; e.g. the
/// one unnamed MechanicalObject of a node is "MechanicalObject1".
std::string sofa_default_name(const SceneComponent& c) {
    const auto class_of = [](const SceneComponent& x) {
        const ComponentSpec* spec = find_component(x.type);
        return spec != nullptr && !spec->sofa_class.empty() ? spec->sofa_class : std::string_view(x.type);
    };
    const std::string_view cls = class_of(c);
    int count = 0;
    for (const auto& other : c.node->components) {
        if (other->name.empty() && class_of(*other) == cls) ++count;
        if (other.get() == &c) break;
    }
    return std::string(cls) + std::to_string(count);
}

std::vector<double> elasticity_values(const Attributes& a, std::string_view name, std::vector<double> fallback,
                                      bool poisson) {
    if (!a.has(name)) return fallback;
    std::vector<double> v = a.numbers(name);
    if (v.empty()) a.fail(name, "is empty");
    for (double x : v) {
        if (poisson && !(x >= 0 && x < 0.5)) a.fail(name, "must be in [0, 0.5), found " + num(x));
        if (!poisson && !(x > 0)) a.fail(name, "must be > 0, found " + num(x));
    }
    return v;
}

bool is_rigid_template(const SceneComponent& c, std::string_view name) {
    if (name.empty() || name == "Vec3d" || name == "Vec3" || name == "Vec3f") return false;
    if (name == "Rigid3d" || name == "Rigid3" || name == "Rigid" || name == "Rigid3f") return true;
    io::throw_element_error(c, "template '" + std::string(name) + "' is not supported (Vec3d or Rigid3d)");
}

void require_vec3_template(const SceneComponent& c) {
    if (is_rigid_template(c, c.template_name))
        io::throw_element_error(c, "template '" + c.template_name + "' is not supported (Vec3d only)");
}

}  // namespace penalty::scene
