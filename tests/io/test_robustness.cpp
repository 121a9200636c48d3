// Nothing crashes or hangs on bad input: every prefix of every committed mesh and scene file,
// and byte-corrupted copies, either load or throw the io layer's own error.

#include "io_test_util.hpp"

#include "penalty/io/mesh.hpp"
#include "penalty/io/scene_file.hpp"
#include "penalty/io/scene_mesh.hpp"
#include "penalty/scene/components.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

namespace penalty::io {
namespace {

using test::data_dir;
using test::write_temp;

std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream out;
    out << in.rdbuf();
    return out.str();
}

// Loads `text` as `name`; returns 1 when it loaded, 0 when it threw LoadError.
int try_load(const std::string& name, const std::string& text) {
    const auto p = write_temp(name, text);
    try {
        (void)load_mesh_file(p);
        return 1;
    } catch (const LoadError&) {
        return 0;
    }
}

TEST(Robustness, EveryPrefixOfEveryMeshFileLoadsOrThrowsLoadError) {
    for (const char* file : {"tetra.obj", "two_tets_v1.msh", "hex_v2.msh", "spheres.sph", "poly.vtk", "grid.vtk"}) {
        SCOPED_TRACE(file);
        const std::string text = slurp(data_dir() / "mesh" / file);
        ASSERT_FALSE(text.empty());
        int loaded = 0;
        for (std::size_t n = 0; n <= text.size(); ++n) {
            loaded += try_load(std::string("prefix_") + file, text.substr(0, n));
        }
        EXPECT_GE(loaded, 1);  // at least the whole file
        EXPECT_EQ(try_load(std::string("whole_") + file, text), 1);
    }
}

TEST(Robustness, CorruptedBytesLoadOrThrowLoadError) {
    std::mt19937 rng(12345);
    const std::string alphabet = "0123456789-+.e \n$#/@abcxyz";
    int failures = 0;
    int total = 0;
    for (const char* file : {"tetra.obj", "two_tets_v1.msh", "hex_v2.msh", "spheres.sph", "poly.vtk", "grid.vtk"}) {
        const std::string text = slurp(data_dir() / "mesh" / file);
        for (int trial = 0; trial < 100; ++trial) {
            std::string copy = text;
            for (int k = 0; k < 3; ++k) {
                copy[rng() % copy.size()] = alphabet[rng() % alphabet.size()];
            }
            failures += 1 - try_load(std::string("corrupt_") + file, copy);
            ++total;
        }
    }
    // the corruption must actually exercise the error paths
    EXPECT_GT(failures, total / 4);
}

TEST(Robustness, EveryPrefixOfASceneParsesOrThrowsSceneError) {
    const std::string text = slurp(data_dir() / "scenes" / "tiny.scn");
    // A prefix is a complete scene exactly when it holds the root's closing tag: every shorter one
    // must be refused with a SceneError (anything else escaping fails the test).
    const std::size_t root_end = text.rfind("</Node>") + std::string_view("</Node>").size();
    ASSERT_NE(text.rfind("</Node>"), std::string::npos);
    std::size_t parsed = 0, refused = 0;
    for (std::size_t n = 0; n <= text.size(); ++n) {
        bool ok = false;
        try {
            const SceneFile s = parse_scene_string(text.substr(0, n), "prefix.scn");
            (void)scene::validate(s);
            ok = true;
        } catch (const SceneError&) {
        }
        EXPECT_EQ(ok, n >= root_end) << "prefix of " << n << " bytes";
        (ok ? parsed : refused) += 1;
    }
    EXPECT_EQ(parsed, text.size() - root_end + 1);
    EXPECT_EQ(refused, root_end);
}

}  // namespace
}  // namespace penalty::io
