// The transform engines' computations (mechanics/transform_engines.cpp): TransformEngine,
// TransformPosition (and its transformation files), MergePoints; closed forms on point sets made here.
#include "penalty/mechanics/regions_of_interest.hpp"
#include "penalty/mechanics/selection_engines.hpp"
#include "penalty/mechanics/transform_engines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

namespace penalty {
namespace {

TEST(TransformEngine, ScaleThenRotationThenTranslation) {
    const std::vector<Vec3> in = {Vec3(1, 0, 0), Vec3(0, 2, 0), Vec3(1, 1, 1)};
    TransformEngineParameters p;
    p.translation = Vec3(10, 0, -1);
    EXPECT_EQ(transform_engine(in, p)[2], Vec3(11, 1, 0));  // translation alone: exact
    p.translation = Vec3::Zero();
    p.scale = Vec3(0.5, 1, 2);
    EXPECT_EQ(transform_engine(in, p)[2], Vec3(0.5, 1, 2));  // scale alone: exact
    // 90° about z after the scale, then the translation: (x, y, z) → (−s_y y, s_x x, s_z z) + t
    p.rotation_deg = Vec3(0, 0, 90);
    p.translation = Vec3(10, 0, 0);
    const std::vector<Vec3> out = transform_engine(in, p);
    EXPECT_NEAR((out[0] - Vec3(10, 0.5, 0)).norm(), 0, 1e-15);
    EXPECT_NEAR((out[1] - Vec3(8, 0, 0)).norm(), 0, 1e-15);
    EXPECT_NEAR((out[2] - Vec3(9, 0.5, 2)).norm(), 0, 1e-15);
    // the inverse undoes it (steps reversed and inverted)
    TransformEngineParameters inv = p;
    inv.inverse = true;
    const std::vector<Vec3> back = transform_engine(out, inv);
    for (std::size_t i = 0; i < in.size(); ++i) EXPECT_NEAR((back[i] - in[i]).norm(), 0, 1e-14);
    // a quaternion rotation after the Euler one: 90° about x
    TransformEngineParameters q;
    q.quaternion = Quat(std::cos(std::numbers::pi / 4), std::sin(std::numbers::pi / 4), 0, 0);
    EXPECT_NEAR((transform_engine(in, q)[1] - Vec3(0, 0, 2)).norm(), 0, 1e-15);
}

TEST(TransformPosition, MethodsAndFixedIndices) {
    const std::vector<Vec3> in = {Vec3(1, 2, 3), Vec3(-1, 0, 4)};
    TransformPositionParameters p;
    p.method = TransformPositionMethod::project_on_plane;
    p.origin = Vec3(0, 0, 1);
    p.normal = Vec3(0, 0, 5);  // normalised by init
    EXPECT_EQ(transform_position(in, p)[0], Vec3(1, 2, 1));
    p.method = TransformPositionMethod::scale;
    p.scale = Vec3(2, 2, 2);
    EXPECT_EQ(transform_position(in, p)[1], Vec3(-2, 0, 7));  // about the origin (0, 0, 1)
    p.method = TransformPositionMethod::scale_translation;
    p.translation = Vec3(1, 1, 1);
    EXPECT_EQ(transform_position(in, p)[0], Vec3(3, 5, 7));
    p.method = TransformPositionMethod::affine;
    p.matrix << 0, -1, 0, 5, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2;  // rotation, translation, w = 2
    EXPECT_EQ(transform_position(in, p)[0], Vec3(1.5, 0.5, 1.5));
    p.fixed_indices = {1};
    EXPECT_EQ(transform_position(in, p)[1], in[1]);
    p.fixed_indices = {2};
    EXPECT_THROW((void)transform_position(in, p), std::invalid_argument);
}

TEST(TransformPosition, TransformationFilesAsSofaReadsThem) {
    const auto dir = std::filesystem::temp_directory_path() / "penalty_transform_files";
    std::filesystem::create_directories(dir);
    {
        std::ofstream(dir / "t.tfm") << "#Insight Transform File V1.0\nTransform: AffineTransform_double_3_3\n"
                                        "Parameters: 1 0 0 0 0 -1 0 1 0 1 2 3\nFixedParameters: 0 0 0\n";
        std::ofstream(dir / "t.trm") << "1 2 3\n0 1 0\n-1 0 0\n0 0 1\n";
        std::ofstream(dir / "t.txt") << "1 0 0 4\n0 1 0 5\n0 0 1 6\n0 0 0 1\n";
        std::ofstream(dir / "bad.txt") << "1 0 0\n";
        std::ofstream(dir / "bad.tfm") << "Parameters: 1 2 3\n";
    }
    const Eigen::Matrix4d tfm = read_affine_transform_file(dir / "t.tfm");
    EXPECT_EQ(tfm(1, 2), -1.0);
    EXPECT_EQ(tfm(2, 1), 1.0);
    // SOFA reads the .tfm translation backwards: t_i = value[11 − i]
    EXPECT_EQ(Vec3(tfm(0, 3), tfm(1, 3), tfm(2, 3)), Vec3(3, 2, 1));
    const Eigen::Matrix4d trm = read_affine_transform_file(dir / "t.trm");
    EXPECT_EQ(Vec3(trm(0, 3), trm(1, 3), trm(2, 3)), Vec3(1, 2, 3));
    EXPECT_EQ(trm(0, 1), 1.0);
    EXPECT_EQ(trm(1, 0), -1.0);
    EXPECT_EQ(read_affine_transform_file(dir / "t.txt")(2, 3), 6.0);
    EXPECT_THROW((void)read_affine_transform_file(dir / "bad.txt"), std::invalid_argument);
    EXPECT_THROW((void)read_affine_transform_file(dir / "bad.tfm"), std::invalid_argument);
    EXPECT_THROW((void)read_affine_transform_file(dir / "missing.tfm"), std::invalid_argument);
    std::filesystem::remove_all(dir);
}

TEST(MergePoints, AdditionAndInjection) {
    const std::vector<Vec3> x1 = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)};
    const std::vector<Vec3> x2 = {Vec3(9, 9, 9), Vec3(8, 8, 8)};
    const MergedPoints added = merge_points(x1, x2, {});
    EXPECT_EQ(added.points.size(), 6u);
    EXPECT_EQ(added.points[4], x2[0]);
    EXPECT_EQ(added.indices1, (std::vector<PointId>{0, 1, 2, 3}));
    EXPECT_EQ(added.indices2, (std::vector<PointId>{4, 5}));
    const MergedPoints injected = merge_points(x1, x2, {3, 1});
    EXPECT_EQ(injected.points.size(), 4u);
    EXPECT_EQ(injected.points[3], x2[0]);
    EXPECT_EQ(injected.points[1], x2[1]);
    EXPECT_EQ(injected.indices2, (std::vector<PointId>{1, 3}));
    EXPECT_EQ(injected.indices1, (std::vector<PointId>{0, 2}));
    EXPECT_THROW((void)merge_points(x1, x2, {0, 1, 2}), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
