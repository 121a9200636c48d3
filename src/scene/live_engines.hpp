#pragma once
// Engines whose input points are a state's positions, which the solve writes
// (`BoxROI position="@dofs.position"`, `TransformEngine input_position="@dofs.position"`), or the
// point output of another such engine (a chain: `BoxROI position="@transform.output_position"`),
// and the Data that read their outputs while the scene runs (docs/python.md, "Engines over moving
// states").
//
// In SOFA each write of the positions marks the engine's input dirty (Data::endEdit →
// DDGNode::setDirtyOutputs, which goes on down a chain of engines), and the engine runs again when
// one of its outputs is next read (Data::getValue → DDGNode::updateIfDirty → DataEngine::update,
// which reads its inputs first and so runs the engines before it). An engine's outputs are a
// function of its inputs alone, so penalty keeps, per such engine, the input points of its last
// run: a read of an output reads the input (running the engine before it, if any) and runs the
// engine again when the points differ (bit for bit). Each read then gives the value SOFA's lazy
// evaluation gives, and an engine nobody reads never runs. A scene without such a link has no
// LiveEngine and pays nothing.
#include "penalty/io/mesh.hpp"
#include "penalty/io/scene_file.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penalty::scene {

/// An engine kind penalty runs again on read: the Data of its input points (the first one the
/// scene sets), the flag that keeps the selection of init (BaseROI's `doUpdate` when 0; written
/// `!name`, MergePoints' `noUpdate`, when 1; empty: none), and the other inputs penalty follows
/// when they link moving data (MeshROI's `ROIposition`, TransformEngine's `translation`; empty
/// entries end the list; written `~name` when SOFA's engine reads the Data without adding it as an
/// input, SphereROI's `centers`), which the re-run reads through LiveEngine::followed. Each kind's
/// builder gives the re-run function (SceneBuilder::add_live_engine), the same function as its
/// build's.
struct LiveEngineKind {
    std::string_view type;
    std::string_view input;
    std::string_view input_alias;
    std::string_view update_flag;
    std::array<std::string_view, 4> followed;
};

/// The engine kinds of `type` that run on read, or null (the table in live_engines.cpp).
[[nodiscard]] const LiveEngineKind* find_live_engine_kind(std::string_view type);

class LiveEngine;

/// Where a live engine reads its input points: the positions of a Vec3d state, a point output of
/// another live engine (which runs first if its own input changed), or, when neither (an engine
/// live for another input), the points of the build.
struct LivePoints {
    const Vec3Object* state = nullptr;
    LiveEngine* engine = nullptr;
    std::string output;        ///< the engine's output (`output_position`)
    std::vector<Vec3> points;  ///< neither: the points of the build, or those of `snapshot_of`
    /// A state whose positions `points` copies at the start of each step and after it
    /// (LiveEngines::update_linked_states): a followed input reads a state as of then.
    const Vec3Object* snapshot_of = nullptr;
    /// The points as of now.
    [[nodiscard]] const std::vector<Vec3>& current() const;
};

/// An input of a live engine besides its points that penalty follows (ProximityROI's `centers`
/// linking a moving state's `position`): SOFA's DataEngine::addInput, dirty when its parent is, so
/// a change runs the engine again. A Data SOFA's engine reads without adding it as an input
/// (SphereROI's `centers`) does not: it is read when the points run the engine, a state's positions
/// as of the step's start while the step runs (SOFA HEAD: the engine ran when the points last
/// moved, at the end of the previous step's solve) and as they are after it.
struct FollowedInput {
    std::string name;  ///< the engine's Data
    LivePoints source;
    std::vector<Vec3> last;   ///< the values of the engine's last run
    bool runs_engine = true;  ///< an input of SOFA's engine: a change runs it again
};

/// One engine over moving points, run on read.
class LiveEngine {
public:
    /// Computes the outputs (`indices`, `meshes`) from the input points.
    using Evaluate = std::function<void(const std::vector<Vec3>& input, LiveEngine& engine)>;

    LiveEngine(const io::SceneComponent& component, LivePoints input, std::vector<FollowedInput> followed,
               Evaluate evaluate)
        : component_(&component),
          input_(std::move(input)),
          followed_(std::move(followed)),
          evaluate_(std::move(evaluate)) {}

    [[nodiscard]] const io::SceneComponent& component() const { return *component_; }
    [[nodiscard]] const LivePoints& input() const { return input_; }
    [[nodiscard]] const std::vector<FollowedInput>& followed_inputs() const { return followed_; }
    [[nodiscard]] std::vector<FollowedInput>& followed_inputs() { return followed_; }
    /// The values of the followed input `name` for the run under way (the re-run function reads
    /// them), or null when penalty does not follow it (the value of the build stands).
    [[nodiscard]] const std::vector<Vec3>* followed(std::string_view name) const;
    /// SOFA's updateIfDirty: runs the engine when its input points or a followed input differ
    /// (bit for bit) from those of its last run, or it never ran. True when it ran.
    bool update_if_dirty();
    /// How many times the engine ran: a reader keeps the count it last took.
    [[nodiscard]] std::uint64_t runs() const { return runs_; }

    /// The outputs by Data name, as the last run wrote them: index lists (BoxROI's `indices`), and
    /// points or element lists (TransformEngine's `output_position`, BoxROI's `trianglesInROI`).
    std::map<std::string, std::vector<PointId>, std::less<>> indices;
    std::map<std::string, io::MeshData, std::less<>> meshes;
    /// Lists of reals (ValuesFromPositions' `values`, `edgeValues`, ...).
    std::map<std::string, std::vector<double>, std::less<>> reals;

private:
    const io::SceneComponent* component_;
    LivePoints input_;
    std::vector<FollowedInput> followed_;
    Evaluate evaluate_;
    std::vector<Vec3> last_input_;
    std::uint64_t runs_ = 0;
};

/// A Data that reads an output of a LiveEngine while the scene runs.
struct LiveEngineReader {
    LiveEngine* engine = nullptr;
    std::string output;
    std::uint64_t seen_runs = 0;  ///< the engine's runs() when this reader last took the output
    /// Runs the engine if its input changed; true when the output is new to this reader.
    bool pull() {
        engine->update_if_dirty();
        if (engine->runs() == seen_runs) return false;
        seen_runs = engine->runs();
        return true;
    }
};

/// A BoxROI whose `box` or `orientedBox` was written after init (SofaQuirkFixes::fix_box_roi_write
/// off): SOFA's BoxROI::roiInit, which orders each box's corners and computes the oriented boxes,
/// ran once, at init; the engine runs again on the written Data without it.
struct BoxRoiWrite {
    bool box_as_written = false;                  ///< `box` tested as written (no corner ordered)
    std::optional<std::string> oriented_of_init;  ///< the `orientedBox` text of init (empty: none), still tested
};

/// The engines of a scene that run on read, and the states whose positions follow one of them.
struct LiveEngines {
    std::vector<std::unique_ptr<LiveEngine>> engines;
    std::map<const io::SceneComponent*, LiveEngine*> by_component;
    /// A MechanicalObject whose `position` links an output of a LiveEngine
    /// (`position="@transform.output_position"`): it takes the output when read.
    struct LinkedState {
        LiveEngineReader reader;
        Vec3Object* state = nullptr;
        std::string path;  ///< the state's SOFA path (errors)
    };
    std::vector<LinkedState> linked_states;

    /// The engine built from `c`, or null.
    [[nodiscard]] LiveEngine* find(const io::SceneComponent& c) const {
        const auto it = by_component.find(&c);
        return it == by_component.end() ? nullptr : it->second;
    }
    /// Takes the positions of the states the engines' followed inputs read (FollowedInput), then
    /// gives each linked state the output of its engine when the engine ran since the state last
    /// took it (SOFA: the state's position Data is dirty and is read). std::invalid_argument when an
    /// output has another number of points than the state. Called before each step's solve and
    /// after the step.
    void update_linked_states();
};

}  // namespace penalty::scene
