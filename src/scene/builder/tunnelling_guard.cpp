// The tunnelling guard of a scene (beyond SOFA, docs/no-tunnelling.md): the noTunnelling
// attributes of the CollisionPipeline / CompositeCollisionPipeline components, or the command
// line's --no-tunnelling (BuildOptions::no_tunnelling), which overrides their mode.
#include "penalty/simulation/tunnelling_guard.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene {

namespace {

TunnellingOptions read_options(const Attributes& a) {
    TunnellingOptions o;
    const std::string mode = a.text("noTunnelling");
    const std::optional<TunnellingMode> m = parse_tunnelling_mode(mode);
    if (!m) a.fail("noTunnelling", "must be off, warn, substep or stiffen, found '" + mode + "'");
    o.mode = *m;
    const std::int64_t halvings = a.integer("noTunnellingMaxHalvings");
    if (halvings < 1 || halvings > 16)
        a.fail("noTunnellingMaxHalvings", "must be in [1, 16], found " + std::to_string(halvings));
    o.max_halvings = int(halvings);
    o.stiffen_fraction = a.real("noTunnellingStiffenFraction");
    if (!(o.stiffen_fraction < 1.0)) a.fail("noTunnellingStiffenFraction", "must be below 1");
    o.max_stiffening = a.real("noTunnellingMaxStiffening");
    if (!(o.max_stiffening >= 1.0) || !std::isfinite(o.max_stiffening))
        a.fail("noTunnellingMaxStiffening", "must be >= 1");
    return o;
}

}  // namespace

void build_tunnelling_guard(SceneBuilder& b) {
    // one guard for the scene (a step is redone whole): the first pipeline that asks for a mode
    // gives the options; another asking for a different mode is an error
    TunnellingOptions options;
    const io::SceneComponent* from = nullptr;
    for (const io::SceneComponent* p : b.pipeline_components()) {
        const TunnellingOptions o = read_options(Attributes(*p));
        if (o.mode == TunnellingMode::off) continue;
        if (from != nullptr && o.mode != options.mode)
            Attributes(*p).fail("noTunnelling", std::string("asks for ") + tunnelling_mode_name(o.mode) + " but " +
                                                    from->describe() + " asks for " +
                                                    tunnelling_mode_name(options.mode) +
                                                    ": the guard is one for the scene");
        if (from == nullptr) {
            options = o;
            from = p;
        }
    }
    if (b.options().no_tunnelling) options.mode = *b.options().no_tunnelling;
    if (options.mode == TunnellingMode::off) return;
    if (b.simulation().collision_steps() != 1 || b.simulation().integration_steps() != 1) {
        const std::string why = "the tunnelling guard checks single steps, not a MultiStepAnimationLoop's";
        if (from != nullptr && !b.options().no_tunnelling) Attributes(*from).fail("noTunnelling", why);
        throw io::SceneError(b.file().path.string() + ": --no-tunnelling " + tunnelling_mode_name(options.mode) + ": " +
                             why);
    }
    b.scene().set_tunnelling(options);
    if (from != nullptr) {
        const std::string mode = tunnelling_mode_name(options.mode);
        b.warn("tunnelling guard: " + mode + " (" + from->describe() + "; beyond SOFA, docs/no-tunnelling.md)");
    }
}

}  // namespace penalty::scene
