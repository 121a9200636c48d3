// `penalty info`: the component tree of a scene and what penalty does with each component.
#include "penalty/io/components.hpp"
#include "penalty/scene/scene.hpp"
#include "scene/attributes.hpp"

#include <set>
#include <sstream>

namespace penalty::scene {

namespace {

void describe_node(const io::SceneNode& node, int depth, const std::set<const io::SceneComponent*>& loaders,
                   const std::set<const io::SceneComponent*>& ignored, std::ostringstream& out) {
    const std::string indent(std::size_t(2 * depth), ' ');
    out << indent << "Node " << (node.parent ? node.path() : std::string("/ (") + node.name + ")");
    for (const char* a : {"dt", "gravity"})
        if (const io::SceneAttribute* at = node.find(a)) out << "  " << a << "=" << at->value;
    out << "\n";
    for (const auto& c : node.components) {
        std::string what;
        if (ignored.count(c.get())) {
            what = "ignored (visual only)";
        } else if (loaders.count(c.get())) {
            what = "loader";
            if (const io::SceneAttribute* f = c->find("filename")) what += " (" + f->value + ")";
        } else {
            what = "simulated";
            const std::vector<std::string> unread = unread_attributes(*c);
            if (!unread.empty()) {
                what += "; not read:";
                for (const auto& a : unread) what += " " + a;
            }
        }
        std::string label = c->type;
        if (!c->template_name.empty()) label += "<" + c->template_name + ">";
        if (!c->name.empty()) label += " '" + c->name + "'";
        out << indent << "  " << label;
        const std::size_t width = 50;
        out << std::string(label.size() + indent.size() + 2 < width ? width - label.size() - indent.size() - 2 : 1, ' ')
            << what << "\n";
    }
    for (const auto& child : node.children) describe_node(*child, depth + 1, loaders, ignored, out);
}

}  // namespace

std::string describe_scene(const io::SceneFile& file) {
    const io::SceneCheck check = io::validate(file);
    std::ostringstream out;
    out << "scene: " << file.path.string() << "\n";
    const std::set<const io::SceneComponent*> loaders(check.loaders.begin(), check.loaders.end());
    const std::set<const io::SceneComponent*> ignored(check.ignored.begin(), check.ignored.end());
    if (file.root) describe_node(*file.root, 0, loaders, ignored, out);
    out << check.physics.size() << " simulated components, " << check.loaders.size() << " loaders";
    if (!check.ignored.empty()) out << "; " << check.summary;
    out << "\n";
    return out.str();
}

}  // namespace penalty::scene
