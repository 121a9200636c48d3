#pragma once
// What a scene keeps of the writes of its Data after init (Scene::LiveEdits; live_writes.cpp).
#include "penalty/scene/scene.hpp"
#include "scene/live_engines.hpp"

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace penalty::scene {

/// The numbers of a written Data (SOFA's text form), each finite (and >= 0, at least one, with
/// `nonnegative`); std::invalid_argument naming `what` and the word otherwise (live_writes.cpp).
std::vector<double> written_numbers(std::string_view text, const std::string& what, bool nonnegative);

struct Scene::LiveEdits {
    /// A write already in the scene's text, taken by the next rebuild; `old` undoes it.
    struct Applied {
        DataOwner owner;
        std::string name;
        std::optional<std::string> old;
    };
    std::vector<Applied> applied;
    /// Writes waiting for their component's reinit(), by (owner path, node?) then Data name.
    std::map<std::pair<std::string, bool>, std::map<std::string, std::string, std::less<>>> at_reinit;
    /// Components or nodes added or removed since the last build.
    bool structure_changed = false;
    /// A rebuild is due before the next step.
    bool rebuild = false;
    /// Inside Scene::step (SOFA's events of the collision phase run there): a rebuild waits for
    /// the next step, the simulation being stepped cannot be replaced.
    bool stepping = false;
    std::uint64_t generation = 0;
    /// Components and nodes added after init, for undoing them when the rebuild fails.
    std::vector<std::pair<const io::SceneNode*, const io::SceneElement*>> added;
    /// SOFA's delay of a root gravity written after init (Scene::set_gravity_write_delay): the
    /// root's child nodes keep their gravity, by path, until the end of the next step.
    std::map<std::string, Vec3> delayed_gravity;
    bool gravity_write_delay = true;
    /// Scenes replaced by a rebuild that changed the list of states (nodes added or removed): kept
    /// until this scene goes, so that what pointed to their state records during a run (the
    /// writers of Scene's run) stays valid.
    std::vector<std::unique_ptr<Scene>> retired;
    /// Components and nodes removed after init: left out of the next build.
    std::set<const io::SceneElement*> removed;
    /// MeshSpringForceField's `stiffness` / `damping` written after init (SOFA's per-spring lists
    /// of SpringForceField, live_quirks.cpp), by component path then Data name: every build of the
    /// component applies them.
    std::map<std::string, std::map<std::string, std::vector<double>>> spring_lists;
    /// BoxROI's `box` / `orientedBox` written after init (live_quirks.cpp), by component path:
    /// every build of the component selects with them.
    std::map<std::string, BoxRoiWrite> box_roi_writes;
    /// This scene is a build again, after writes while the scene ran (Scene::rebuild): written Data
    /// SOFA takes without an error may leave a component Invalid (ConstantForceField's `forces`
    /// and `indices` of different counts), where a scene file's are refused.
    bool rebuilt = false;
    /// Engine outputs that are lists of reals (ValuesFromPositions' `values`), by engine and Data,
    /// as the build computed them (a live engine's own are LiveEngine::reals).
    std::map<std::pair<const io::SceneComponent*, std::string>, std::vector<double>> engine_reals;
    /// Engines whose lists of reals penalty does not compute as SOFA, with why (a read raises it).
    std::map<const io::SceneComponent*, std::string> refused_reals;
    /// Engines over moving states, run on read, and their readers (live_engines.cpp); null when
    /// the scene has none. A rebuild takes the fresh scene's.
    std::unique_ptr<LiveEngines> engines;
    /// Connects the readers of `scene`'s live engines once it is built (live_engines.cpp).
    static void wire_engines(Scene& scene);
    /// The states whose position follows a live engine take its output if it changed (a read).
    void update_engines() const {
        if (engines) engines->update_linked_states();
    }
    /// The live engine built from `c`, or null.
    [[nodiscard]] LiveEngine* engine(const io::SceneComponent& c) const { return engines ? engines->find(c) : nullptr; }
};

}  // namespace penalty::scene
