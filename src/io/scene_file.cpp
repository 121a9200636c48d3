#include "penalty/io/scene_file.hpp"

#include "io/text.hpp"
#include "penalty/io/data_path.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>

namespace penalty::io {

// ---------------------------------------------------------------------------------------------
// tree

const SceneAttribute* SceneElement::find(std::string_view attribute) const {
    for (const auto& a : attributes) {
        if (a.name == attribute) return &a;
    }
    return nullptr;
}

std::string SceneElement::describe() const { return name.empty() ? type : type + " '" + name + "'"; }

const SceneNode* SceneNode::child(std::string_view child_name) const {
    for (const auto& c : children) {
        if (c->name == child_name) return c.get();
    }
    return nullptr;
}

const SceneComponent* SceneNode::component(std::string_view component_name) const {
    for (const auto& c : components) {
        if (c->name == component_name) return c.get();
    }
    return nullptr;
}

std::string SceneNode::path() const {
    if (parent == nullptr) return "/";
    const std::string up = parent->path();
    return (up == "/" ? std::string() : up) + "/" + name;
}

std::filesystem::path SceneFile::directory() const {
    if (path.empty()) return ".";
    const auto dir = path.parent_path();
    return dir.empty() ? std::filesystem::path(".") : dir;
}

// ---------------------------------------------------------------------------------------------
// parsing

namespace {

std::string xml_error_text(tinyxml2::XMLError error) {
    switch (error) {
        case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT:
            return "element closed by a mismatched tag";
        case tinyxml2::XML_ERROR_PARSING:
            return "unclosed element or malformed document";
        case tinyxml2::XML_ERROR_PARSING_ELEMENT:
            return "malformed or unclosed element";
        case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE:
            return "malformed attribute";
        case tinyxml2::XML_ERROR_PARSING_TEXT:
            return "malformed text";
        case tinyxml2::XML_ERROR_PARSING_COMMENT:
            return "malformed comment";
        case tinyxml2::XML_ERROR_PARSING_DECLARATION:
            return "malformed declaration";
        case tinyxml2::XML_ERROR_EMPTY_DOCUMENT:
            return "empty document";
        default:
            return tinyxml2::XMLDocument::ErrorIDToName(error);
    }
}

[[noreturn]] void scene_fail(const std::string& file, int line, const std::string& what) {
    throw SceneError(file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + what);
}

/// What the reading of one scene shares across its included files.
struct ReadContext {
    /// Folders searched for an included file after the including file's own folder.
    std::vector<std::filesystem::path> data_dirs;
    /// The files being read, outermost first (the scene, then each open `<include>`'s file),
    /// as given and as lexically normal absolute paths (for loop detection).
    std::vector<std::string> open_labels;
    std::vector<std::filesystem::path> open_files;
    /// `file:line` of each open `<include>` element, outermost first.
    std::vector<std::string> include_sites;
};

/// " (included from a.xml:3, included from scene.scn:12)" for an element read inside includes.
std::string included_from_text(const ReadContext& context) {
    std::string out;
    for (auto it = context.include_sites.rbegin(); it != context.include_sites.rend(); ++it) {
        out += (out.empty() ? " (included from " : ", included from ") + *it;
    }
    return out.empty() ? out : out + ")";
}

void read_attributes(const tinyxml2::XMLElement& xml, SceneElement& out, std::string* template_name) {
    for (const tinyxml2::XMLAttribute* a = xml.FirstAttribute(); a != nullptr; a = a->Next()) {
        const std::string_view name = a->Name();
        if (name == "name") {
            out.name = a->Value();
        } else if (name == "template" && template_name != nullptr) {
            *template_name = a->Value();
        } else {
            out.attributes.push_back(SceneAttribute{std::string(name), a->Value(), a->GetLineNum()});
        }
    }
}

void read_node(const tinyxml2::XMLElement& xml, SceneNode& node, const std::string& file, int depth,
               ReadContext& context);

std::unique_ptr<SceneComponent> read_component(const tinyxml2::XMLElement& xml, const std::string& file,
                                               const ReadContext& context) {
    auto component = std::make_unique<SceneComponent>();
    component->type = xml.Name();
    component->file = file;
    component->included_from = included_from_text(context);
    component->line = xml.GetLineNum();
    read_attributes(xml, *component, &component->template_name);
    if (component->type == "Object") {  // SOFA's older syntax: <Object type="MechanicalObject" .../>
        const auto it = std::find_if(component->attributes.begin(), component->attributes.end(),
                                     [](const SceneAttribute& a) { return a.name == "type"; });
        if (it == component->attributes.end() || it->value.empty()) {
            scene_fail(file, component->line, "<Object> without a 'type' attribute" + component->included_from);
        }
        component->type = it->value;
        component->attributes.erase(it);
    }
    return component;
}

void add_component(SceneNode& node, std::unique_ptr<SceneComponent> component) {
    component->node = &node;
    component->index = node.components.size();
    node.components.push_back(std::move(component));
}

void add_child(SceneNode& node, std::unique_ptr<SceneNode> child) {
    child->parent = &node;
    node.children.push_back(std::move(child));
}

/// One attribute of an `<include>` element, written onto the included elements as SOFA's
/// XML loader does (sofa::simulation::xml::includeNode, then recReplaceAttribute, applied in
/// ObjectElement::initNode): a component that already has the attribute gets the include's
/// value; the attribute is never added, and nodes keep theirs (NodeElement::initNode ignores
/// the replacements). `only_named` ("" = every element) restricts it to elements of that name
/// (SOFA's `Name__attribute` form). Since every SOFA element has a `name` data, `name` always
/// applies; `template` applies where one is written.
void replace_attribute(SceneNode& tree, std::string_view only_named, const SceneAttribute& replacement) {
    const auto replace_in = [&](SceneComponent& c) {
        if (!only_named.empty() && c.name != only_named) return;
        if (replacement.name == "name") {
            c.name = replacement.value;
        } else if (replacement.name == "template") {
            if (!c.template_name.empty()) c.template_name = replacement.value;
        } else {
            for (auto& a : c.attributes) {
                if (a.name == replacement.name) a.value = replacement.value;
            }
        }
    };
    for (auto& c : tree.components) replace_in(*c);
    for (auto& child : tree.children) replace_attribute(*child, only_named, replacement);
}

/// Deepest nesting of `<include>` elements (SOFA has no limit; a loop is reported as such).
constexpr std::size_t kMaxIncludeDepth = 16;

/// `<include href="Objects/X.xml" name=".." attr="value" Name__attr="value"/>` in `node`, with
/// SOFA's semantics (sofa::simulation::xml::includeNode and createNode):
///  - `href` is looked for in the including file's folder, then the data folders
///    (FileRepository::findFileFromFile: the base file's folder, then SOFA's data path);
///  - the included file's root element (a node or one component) is read, its own includes
///    expanded first;
///  - `name` renames that root; every other attribute is replaced in the included tree
///    (replace_attribute), in the include element's attribute order, after the nested includes'
///    own replacements (so the outer include wins);
///  - a root node named `Group` or `_Group_` (after renaming) is dissolved: its components and
///    child nodes are added to `node` (INCLUDE_NODE_GROUP); otherwise the root is added as a
///    child node (or component) of `node` (INCLUDE_NODE_CHILD).
/// SOFA's `_Merge_` roots (INCLUDE_NODE_MERGE) are refused.
void read_include(const tinyxml2::XMLElement& xml, SceneNode& node, const std::string& file, int depth,
                  ReadContext& context) {
    const int line = xml.GetLineNum();
    const std::string site = file + ":" + std::to_string(line);
    const auto fail = [&](const std::string& what) {
        scene_fail(file, line, "<include>: " + what + included_from_text(context));
    };
    const char* href = xml.Attribute("href");
    if (href == nullptr || *href == '\0') fail("no 'href' attribute (the included file)");

    const std::filesystem::path including_dir = std::filesystem::path(file).parent_path();
    std::filesystem::path included;
    try {
        included = resolve_data_file(href, including_dir, context.data_dirs);
    } catch (const LoadError& e) {
        fail(e.what());
    }
    const std::filesystem::path identity = std::filesystem::absolute(included).lexically_normal();
    for (std::size_t i = 0; i < context.open_files.size(); ++i) {
        if (context.open_files[i] != identity) continue;
        std::string chain;
        for (std::size_t k = i; k < context.open_labels.size(); ++k) chain += context.open_labels[k] + " includes ";
        fail("include loop: " + chain + included.string());
    }
    if (context.include_sites.size() >= kMaxIncludeDepth) {
        fail("includes nested more than " + std::to_string(kMaxIncludeDepth) + " levels deep");
    }

    std::string text;
    try {
        text = detail::read_file(included);
    } catch (const LoadError& e) {
        fail(e.what());
    }
    const std::string label = included.string();
    context.include_sites.push_back(site);
    context.open_labels.push_back(label);
    context.open_files.push_back(identity);
    const std::string from = included_from_text(context);

    tinyxml2::XMLDocument doc(true, tinyxml2::PRESERVE_WHITESPACE);
    const tinyxml2::XMLError error = doc.Parse(text.data(), text.size());
    if (error != tinyxml2::XML_SUCCESS)
        scene_fail(label, doc.ErrorLineNum(), "XML error: " + xml_error_text(error) + from);
    const tinyxml2::XMLElement* root = doc.RootElement();
    if (root == nullptr) scene_fail(label, 0, "XML error: empty document" + from);
    const std::string_view root_tag = root->Name();
    if (root_tag == "include")
        scene_fail(label, root->GetLineNum(), "the root of an included file cannot be an <include>" + from);

    // The included tree, under a holder node that stands for SOFA's returned element.
    SceneNode holder;
    if (root_tag == "Node") {
        auto child = std::make_unique<SceneNode>();
        read_node(*root, *child, label, depth + 1, context);
        add_child(holder, std::move(child));
    } else {
        add_component(holder, read_component(*root, label, context));
    }
    SceneElement& included_root = holder.children.empty() ? static_cast<SceneElement&>(*holder.components.front())
                                                          : static_cast<SceneElement&>(*holder.children.front());
    for (const tinyxml2::XMLAttribute* a = xml.FirstAttribute(); a != nullptr; a = a->Next()) {
        const std::string_view name = a->Name();
        if (name == "href") continue;
        if (name == "name") {
            included_root.name = a->Value();
            continue;
        }
        const std::size_t separator = name.find("__");
        const std::string_view only_named =
            separator == std::string_view::npos ? std::string_view() : name.substr(0, separator);
        const std::string_view attribute = separator == std::string_view::npos ? name : name.substr(separator + 2);
        replace_attribute(holder, only_named, SceneAttribute{std::string(attribute), a->Value(), a->GetLineNum()});
    }
    context.include_sites.pop_back();
    context.open_labels.pop_back();
    context.open_files.pop_back();

    if (holder.children.empty()) {
        add_component(node, std::move(holder.components.front()));
        return;
    }
    std::unique_ptr<SceneNode> root_node = std::move(holder.children.front());
    if (root_node->name == "_Merge_") {
        scene_fail(label, root_node->line, "SOFA's '_Merge_' included node is not supported by penalty" + from);
    }
    if (root_node->name == "Group" || root_node->name == "_Group_") {
        for (auto& c : root_node->components) add_component(node, std::move(c));
        for (auto& n : root_node->children) add_child(node, std::move(n));
        return;
    }
    add_child(node, std::move(root_node));
}

void read_node(const tinyxml2::XMLElement& xml, SceneNode& node, const std::string& file, int depth,
               ReadContext& context) {
    if (depth > 256)
        scene_fail(file, xml.GetLineNum(), "nodes nested more than 256 levels deep" + included_from_text(context));
    node.type = "Node";
    node.file = file;
    node.included_from = included_from_text(context);
    node.line = xml.GetLineNum();
    read_attributes(xml, node, nullptr);
    for (const tinyxml2::XMLElement* e = xml.FirstChildElement(); e != nullptr; e = e->NextSiblingElement()) {
        const std::string_view tag = e->Name();
        if (tag == "Node") {
            auto child = std::make_unique<SceneNode>();
            read_node(*e, *child, file, depth + 1, context);
            add_child(node, std::move(child));
        } else if (tag == "include") {
            read_include(*e, node, file, depth, context);
        } else {
            add_component(node, read_component(*e, file, context));
        }
    }
}

SceneFile parse(const char* xml, std::size_t size, std::filesystem::path path, const std::string& label,
                const std::vector<std::filesystem::path>& data_dirs) {
    tinyxml2::XMLDocument doc(true, tinyxml2::PRESERVE_WHITESPACE);
    const tinyxml2::XMLError error = doc.Parse(xml, size);
    if (error != tinyxml2::XML_SUCCESS) {
        scene_fail(label, doc.ErrorLineNum(), "XML error: " + xml_error_text(error));
    }
    const tinyxml2::XMLElement* root = doc.RootElement();
    if (root == nullptr) scene_fail(label, 0, "XML error: empty document");
    if (std::string_view(root->Name()) != "Node") {
        scene_fail(label, root->GetLineNum(), "root element must be <Node>, found <" + std::string(root->Name()) + ">");
    }
    ReadContext context;
    context.data_dirs = data_dirs;
    if (!path.empty()) {
        context.open_labels.push_back(label);
        context.open_files.push_back(std::filesystem::absolute(path).lexically_normal());
    }
    SceneFile scene;
    scene.path = std::move(path);
    scene.root = std::make_unique<SceneNode>();
    read_node(*root, *scene.root, label, 0, context);
    return scene;
}

}  // namespace

SceneFile parse_scene_file(const std::filesystem::path& path, const std::vector<std::filesystem::path>& data_dirs) {
    std::string text;
    try {
        text = detail::read_file(path);
    } catch (const LoadError& e) {
        throw SceneError(e.what());
    }
    return parse(text.data(), text.size(), path, path.string(), data_dirs);
}

SceneFile parse_scene_string(std::string_view xml, const std::string& file_label,
                             const std::vector<std::filesystem::path>& data_dirs) {
    return parse(xml.data(), xml.size(), {}, file_label, data_dirs);
}

// ---------------------------------------------------------------------------------------------
// typed attributes

void throw_attribute_error(const SceneElement& element, std::string_view attribute, const std::string& what) {
    const SceneAttribute* a = element.find(attribute);
    const int line = a != nullptr ? a->line : element.line;
    throw SceneError(element.file + ":" + std::to_string(line) + ": " + element.describe() + ": attribute '" +
                     std::string(attribute) + "': " + what + element.included_from);
}

void throw_element_error(const SceneElement& element, const std::string& what) {
    throw SceneError(element.file + ":" + std::to_string(element.line) + ": " + element.describe() + ": " + what +
                     element.included_from);
}

namespace {

// The attribute's value, refusing links where a value is expected.
const std::string* value_of(const SceneElement& e, std::string_view attr) {
    const SceneAttribute* a = e.find(attr);
    if (a == nullptr) return nullptr;
    if (is_link(a->value)) {
        throw_attribute_error(e, attr, "expected a value, found the link '" + a->value + "' (resolve it first)");
    }
    return &a->value;
}

std::string shorten(std::string_view s) {
    return s.size() <= 40 ? std::string(s) : std::string(s.substr(0, 37)) + "...";
}

/// Refuses an inline list of more than kMaxInlineValues numbers before parsing it (counting
/// blank-separated tokens costs one pass over the text, no allocation).
void check_inline_size(const SceneElement& e, std::string_view attr, std::string_view text) {
    std::size_t tokens = 0;
    bool in_token = false;
    for (const char ch : text) {
        const bool blank = ch == ' ' || ch == '\t' || ch == '\r' || ch == '\n' || ch == '\v' || ch == '\f';
        if (!blank && !in_token) ++tokens;
        in_token = !blank;
    }
    if (tokens > kMaxInlineValues) {
        throw_attribute_error(e, attr,
                              std::to_string(tokens) + " values, more than penalty's limit of " +
                                  std::to_string(kMaxInlineValues) +
                                  " in one attribute (put large data in a mesh file)");
    }
}

double number_or_throw(const SceneElement& e, std::string_view attr, std::string_view token) {
    const auto v = detail::parse_double(token);
    if (!v) throw_attribute_error(e, attr, "expected a number, found '" + shorten(token) + "'");
    if (const auto problem = detail::magnitude_problem(*v))
        throw_attribute_error(e, attr, "'" + shorten(token) + "': " + *problem);
    return *v;
}

}  // namespace

std::optional<std::string> get_string(const SceneElement& e, std::string_view attr) {
    const SceneAttribute* a = e.find(attr);
    if (a == nullptr) return std::nullopt;
    return a->value;
}

std::optional<double> get_double(const SceneElement& e, std::string_view attr) {
    const std::string* v = value_of(e, attr);
    if (v == nullptr) return std::nullopt;
    const auto tokens = detail::split_blanks(*v);
    if (tokens.size() != 1) {
        throw_attribute_error(e, attr, "expected one number, found '" + shorten(*v) + "'");
    }
    return number_or_throw(e, attr, tokens[0]);
}

double get_double_or(const SceneElement& e, std::string_view attr, double fallback) {
    return get_double(e, attr).value_or(fallback);
}

std::optional<std::int64_t> get_int(const SceneElement& e, std::string_view attr) {
    const std::string* v = value_of(e, attr);
    if (v == nullptr) return std::nullopt;
    const auto tokens = detail::split_blanks(*v);
    const auto value = tokens.size() == 1 ? detail::parse_int(tokens[0]) : std::nullopt;
    if (!value) throw_attribute_error(e, attr, "expected an integer, found '" + shorten(*v) + "'");
    return *value;
}

std::int64_t get_int_or(const SceneElement& e, std::string_view attr, std::int64_t fallback) {
    return get_int(e, attr).value_or(fallback);
}

std::optional<bool> get_bool(const SceneElement& e, std::string_view attr) {
    const std::string* v = value_of(e, attr);
    if (v == nullptr) return std::nullopt;
    std::string lower(detail::trim(*v));
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower == "1" || lower == "true") return true;
    if (lower == "0" || lower == "false") return false;
    throw_attribute_error(e, attr, "expected a boolean (0, 1, true or false), found '" + shorten(*v) + "'");
}

bool get_bool_or(const SceneElement& e, std::string_view attr, bool fallback) {
    return get_bool(e, attr).value_or(fallback);
}

std::vector<double> get_doubles(const SceneElement& e, std::string_view attr) {
    const std::string* v = value_of(e, attr);
    if (v == nullptr) return {};
    check_inline_size(e, attr, *v);
    std::vector<double> out;
    for (const auto token : detail::split_blanks(*v)) out.push_back(number_or_throw(e, attr, token));
    return out;
}

std::optional<Vec3> get_vec3(const SceneElement& e, std::string_view attr) {
    if (!e.has(attr)) return std::nullopt;
    const std::vector<double> v = get_doubles(e, attr);
    if (v.size() != 3) {
        throw_attribute_error(e, attr, "expected 3 numbers, found " + std::to_string(v.size()));
    }
    return Vec3(v[0], v[1], v[2]);
}

Vec3 get_vec3_or(const SceneElement& e, std::string_view attr, const Vec3& fallback) {
    return get_vec3(e, attr).value_or(fallback);
}

std::vector<Vec3> get_vec3_list(const SceneElement& e, std::string_view attr) {
    const std::vector<double> v = get_doubles(e, attr);
    if (v.size() % 3 != 0) {
        throw_attribute_error(e, attr, "expected a multiple of 3 numbers, found " + std::to_string(v.size()));
    }
    std::vector<Vec3> out;
    out.reserve(v.size() / 3);
    for (std::size_t i = 0; i < v.size(); i += 3) out.emplace_back(v[i], v[i + 1], v[i + 2]);
    return out;
}

std::vector<RigidFrame> get_rigid_list(const SceneElement& e, std::string_view attr) {
    const std::vector<double> v = get_doubles(e, attr);
    if (v.size() % 7 != 0) {
        throw_attribute_error(
            e, attr, "expected a multiple of 7 numbers (x y z qx qy qz qw), found " + std::to_string(v.size()));
    }
    std::vector<RigidFrame> out;
    for (std::size_t i = 0; i < v.size(); i += 7) {
        RigidFrame f;
        f.center = Vec3(v[i], v[i + 1], v[i + 2]);
        f.orientation = Quat(v[i + 6], v[i + 3], v[i + 4], v[i + 5]);  // Eigen: (w, x, y, z)
        const double norm = f.orientation.norm();
        if (!(norm > 0.0)) {
            throw_attribute_error(e, attr, "rigid frame " + std::to_string(i / 7) + " has a zero quaternion");
        }
        out.push_back(f);  // as written, as SOFA's RigidCoord reads it (not normalized)
    }
    return out;
}

std::vector<PointId> get_indices(const SceneElement& e, std::string_view attr) {
    const std::string* v = value_of(e, attr);
    if (v == nullptr) return {};
    check_inline_size(e, attr, *v);
    std::vector<PointId> out;
    const auto index = [&](std::string_view token, std::string_view text) {
        const auto value = detail::parse_int(text);
        if (!value || *value < 0 || *value > std::numeric_limits<PointId>::max()) {
            throw_attribute_error(e, attr, "expected a non-negative integer index, found '" + shorten(token) + "'");
        }
        return *value;
    };
    // SOFA's vector<unsigned int>::read: "A-B" is every index from A to B (down when B < A), and
    // "A-B-S" steps by S (its sign wins: A and B swap when it points the other way).
    constexpr std::int64_t kMostIndices = 100'000'000;
    for (const auto token : detail::split_blanks(*v)) {
        const std::size_t hyphen = token.find('-', 1);
        if (hyphen == std::string_view::npos) {
            out.push_back(static_cast<PointId>(index(token, token)));
            continue;
        }
        std::int64_t first = index(token, token.substr(0, hyphen));
        const std::size_t hyphen2 = token.find('-', hyphen + 2);
        std::int64_t last =
            index(token, token.substr(hyphen + 1, hyphen2 == std::string_view::npos ? std::string_view::npos
                                                                                    : hyphen2 - hyphen - 1));
        std::int64_t step = first <= last ? 1 : -1;
        if (hyphen2 != std::string_view::npos) {
            const auto given = detail::parse_int(token.substr(hyphen2 + 1));
            if (!given)
                throw_attribute_error(e, attr, "expected a range A-B or A-B-STEP, found '" + shorten(token) + "'");
            if (*given != 0) step = *given;
            if ((last - first) * step < 0) std::swap(first, last);
        }
        const std::int64_t count = (last - first) / step + 1;
        if (count > kMostIndices || static_cast<std::int64_t>(out.size()) + count > kMostIndices)
            throw_attribute_error(e, attr, "the range '" + shorten(token) + "' gives more than 10^8 indices");
        if (step < 0) {
            for (std::int64_t t = first; t > last; t += step) out.push_back(static_cast<PointId>(t));
            out.push_back(static_cast<PointId>(last));
        } else {
            for (std::int64_t t = first; t <= last; t += step) out.push_back(static_cast<PointId>(t));
        }
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// links

bool is_link(std::string_view value) {
    const std::string_view t = detail::trim(value);
    return !t.empty() && t.front() == '@';
}

namespace {

[[noreturn]] void broken(const SceneComponent& from, std::string_view attr, std::string_view link,
                         const std::string& why) {
    throw_attribute_error(from, attr, "broken link '@" + std::string(link) + "': " + why);
}

}  // namespace

LinkTarget resolve_link_text(const SceneComponent& from, std::string_view link, std::string_view attr) {
    link = detail::trim(link);
    if (!link.empty() && link.front() == '@') link.remove_prefix(1);
    if (from.node == nullptr) broken(from, attr, link, "the component is not in a scene tree");

    // split "path.data": the data name follows the last '.' of the last segment (not "." / "..")
    std::string_view path = link;
    std::string data;
    {
        const std::size_t slash = link.rfind('/');
        const std::size_t seg_start = slash == std::string_view::npos ? 0 : slash + 1;
        const std::string_view segment = link.substr(seg_start);
        const std::size_t dot = segment.rfind('.');
        if (segment != "." && segment != ".." && dot != std::string_view::npos && dot > 0) {
            data = std::string(segment.substr(dot + 1));
            path = link.substr(0, seg_start + dot);
            if (data.empty()) broken(from, attr, link, "empty data name after '.'");
        }
    }

    LinkTarget target;
    // self reference / index in the node's component list
    if (path.empty()) {
        target.component = &from;
        target.data = data;
        return target;
    }
    if (path.front() == '[') {
        if (path.back() != ']') broken(from, attr, link, "malformed index (expected [-k])");
        const auto k = detail::parse_int(path.substr(1, path.size() - 2));
        if (!k || *k > 0) broken(from, attr, link, "malformed index (expected [-k] with k >= 0)");
        const auto back = static_cast<std::size_t>(-*k);
        if (back > from.index) {
            broken(
                from, attr, link,
                "only " + std::to_string(from.index) + " component(s) before it in node '" + from.node->path() + "'");
        }
        target.component = from.node->components[from.index - back].get();
        target.data = data;
        return target;
    }

    const SceneNode* node = from.node;
    const SceneComponent* component = nullptr;
    bool based = false;
    std::size_t pos = 0;
    if (path.front() == '/') {
        while (node->parent != nullptr) node = node->parent;
        pos = 1;
        based = true;
    }
    while (pos < path.size()) {
        const std::size_t end = std::min(path.find('/', pos), path.size());
        const std::string_view segment = path.substr(pos, end - pos);
        pos = end + 1;
        if (segment.empty()) continue;  // extra '/'
        if (component != nullptr) {
            broken(from, attr, link,
                   "'" + component->describe() + "' is a component, it has no child '" + std::string(segment) + "'");
        }
        if (segment == ".") {
            based = true;
            continue;
        }
        if (segment == "..") {
            if (node->parent == nullptr) broken(from, attr, link, "'..' goes above the root node");
            node = node->parent;
            based = true;
            continue;
        }
        const SceneNode* search = node;
        for (;;) {
            if (const SceneNode* child = search->child(segment)) {
                node = child;
                break;
            }
            if (const SceneComponent* c = search->component(segment)) {
                node = search;
                component = c;
                break;
            }
            if (based || search->parent == nullptr) {
                broken(from, attr, link,
                       "no node or component named '" + std::string(segment) + "' in node '" + node->path() + "'" +
                           (based ? "" : " or its ancestors"));
            }
            search = search->parent;
        }
        based = true;
    }
    if (component != nullptr) {
        target.component = component;
    } else {
        target.node = node;
    }
    target.data = data;
    return target;
}

LinkTarget resolve_link(const SceneComponent& from, std::string_view attr) {
    const SceneAttribute* a = from.find(attr);
    if (a == nullptr) throw_attribute_error(from, attr, "missing (a link was expected)");
    const auto tokens = detail::split_blanks(a->value);
    if (tokens.size() != 1 || !is_link(tokens[0])) {
        throw_attribute_error(from, attr, "expected one link '@...', found '" + shorten(a->value) + "'");
    }
    return resolve_link_text(from, tokens[0], attr);
}

std::vector<LinkTarget> resolve_links(const SceneComponent& from, std::string_view attr) {
    const SceneAttribute* a = from.find(attr);
    if (a == nullptr) return {};
    std::vector<LinkTarget> out;
    for (const auto token : detail::split_blanks(a->value)) {
        if (!is_link(token)) throw_attribute_error(from, attr, "expected links '@...', found '" + shorten(token) + "'");
        out.push_back(resolve_link_text(from, token, attr));
    }
    return out;
}

}  // namespace penalty::io
