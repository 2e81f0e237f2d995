// Display profiles: the shipped data files, direction -> display mapping, vergence.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "profiles/display_profile.hpp"

using namespace fovea::drivers::profiles;

namespace {

constexpr double kDeg = 0.017453292519943295;

Vec3 dir_deg(double ax, double ay) { return {std::tan(ax * kDeg), std::tan(ay * kDeg), 1.0}; }

Vec3 normalize(Vec3 v) {
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return {v[0] / n, v[1] / n, v[2] / n};
}

TEST(DisplayProfiles, ShippedProfilesLoadAndListed) {
    const auto names = list_profiles();
    for (const char* n : {"oculus-dk2-patney", "generic-2x1440x1600", "desktop-24in-60cm"}) {
        EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
        auto p = find_profile(n);
        ASSERT_TRUE(p.ok()) << p.error().message;
        EXPECT_EQ(p->name, n);
    }
}

TEST(DisplayProfiles, PatneyDk2HasTheirResolutionAndFieldOfView) {
    auto p = find_profile("oculus-dk2-patney");
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ(p->kind, DisplayKind::kHmd);
    EXPECT_EQ(p->left.width_px, 1184);
    EXPECT_EQ(p->left.height_px, 1464);
    EXPECT_DOUBLE_EQ(p->left.fov_up_deg + p->left.fov_down_deg, 110.0);
    // Square pixels at the centre, as the horizontal half-angle was derived.
    EXPECT_NEAR(p->left.pixels_per_degree_x(), p->left.pixels_per_degree_y(), 1e-3);
    // 55 degrees up is the top edge; straight ahead is the centre.
    const auto top = map_direction(p->left, dir_deg(0, -55));
    EXPECT_NEAR(top.norm_y, 0.0, 1e-12);
    EXPECT_NEAR(top.deg_y, -55.0, 1e-9);
    const auto c = map_direction(p->left, {0, 0, 1});
    EXPECT_DOUBLE_EQ(c.norm_x, 0.5);
    EXPECT_DOUBLE_EQ(c.norm_y, 0.5);
    EXPECT_TRUE(c.inside);
    EXPECT_NEAR(c.px_x, 592.0, 1e-9);
}

TEST(DisplayProfiles, AsymmetricViewPutsTheOpticalAxisTowardsTheNose) {
    auto p = find_profile("generic-2x1440x1600");
    ASSERT_TRUE(p.ok()) << p.error().message;
    const double expect = std::tan(52 * kDeg) / (std::tan(52 * kDeg) + std::tan(46 * kDeg));
    EXPECT_NEAR(p->left.center_x(), expect, 1e-12);
    EXPECT_NEAR(p->right.center_x(), 1 - expect, 1e-12);
    EXPECT_NEAR(map_direction(p->left, {0, 0, 1}).norm_x, expect, 1e-12);
    EXPECT_NEAR(map_direction(p->left, dir_deg(-52, 0)).norm_x, 0.0, 1e-12);
    EXPECT_NEAR(map_direction(p->left, dir_deg(46, 0)).norm_x, 1.0, 1e-12);
    EXPECT_FALSE(map_direction(p->left, dir_deg(50, 0)).inside);  // past the nasal edge
    EXPECT_TRUE(map_direction(p->left, dir_deg(50, 0)).valid);
}

TEST(DisplayProfiles, MonitorMappingAgreesWithTheGazeChainsDisplayGeometry) {
    auto p = find_profile("desktop-24in-60cm");
    ASSERT_TRUE(p.ok()) << p.error().message;
    const auto g = p->display_geometry();
    EXPECT_DOUBLE_EQ(g.width_m, 0.531);
    EXPECT_DOUBLE_EQ(g.distance_m, 0.60);
    EXPECT_NEAR(p->left.pixels_per_degree_x(), g.pixels_per_degree(), 1e-9);
    for (double ax : {-20.0, -5.0, 0.0, 3.0, 17.5}) {
        for (double ay : {-12.0, 0.0, 9.0}) {
            const auto m = map_direction(p->left, dir_deg(ax, ay));
            double nx = 0, ny = 0;
            g.to_normalized(ax, ay, nx, ny);
            EXPECT_NEAR(m.norm_x, nx, 1e-12);
            EXPECT_NEAR(m.norm_y, ny, 1e-12);
            EXPECT_NEAR(m.deg_x, ax, 1e-9);
            EXPECT_NEAR(m.deg_y, ay, 1e-9);
        }
    }
}

TEST(DisplayProfiles, NormalizedToDirectionRoundTrips) {
    auto p = find_profile("generic-2x1440x1600");
    ASSERT_TRUE(p.ok());
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    for (int i = 0; i < 1000; ++i) {
        const double nx = u(rng), ny = u(rng);
        const auto d = direction_from_normalized(p->right, nx, ny);
        EXPECT_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-12);
        const auto m = map_direction(p->right, d);
        EXPECT_NEAR(m.norm_x, nx, 1e-12);
        EXPECT_NEAR(m.norm_y, ny, 1e-12);
    }
}

TEST(DisplayProfiles, DirectionsBehindTheEyeOrNotFiniteMapToNothing) {
    auto p = find_profile("oculus-dk2-patney");
    ASSERT_TRUE(p.ok());
    EXPECT_FALSE(map_direction(p->left, {0, 0, -1}).valid);
    EXPECT_FALSE(map_direction(p->left, {1, 0, 0}).valid);
    EXPECT_FALSE(map_direction(p->left, {NAN, 0, 1}).valid);
    EXPECT_FALSE(map_direction(p->left, {0, INFINITY, 1}).valid);
    const auto grazing = map_direction(p->left, {1, 0, 1e-300});
    EXPECT_FALSE(grazing.inside);
}

TEST(Vergence, RecoversTheFixatedPoint) {
    auto p = find_profile("oculus-dk2-patney");
    ASSERT_TRUE(p.ok());
    const double h = p->ipd_m / 2;
    for (const Vec3 target : {Vec3{0.1, -0.05, 0.5}, Vec3{0, 0, 2.0}, Vec3{-0.3, 0.2, 0.35}}) {
        const Vec3 l = normalize({target[0] + h, target[1], target[2]});
        const Vec3 r = normalize({target[0] - h, target[1], target[2]});
        const auto v = vergence(*p, l, r);
        ASSERT_TRUE(v.valid);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(v.point_m[i], target[i], 1e-9);
        EXPECT_NEAR(v.miss_m, 0.0, 1e-9);
        EXPECT_NEAR(
            v.distance_m,
            std::sqrt(target[0] * target[0] + target[1] * target[1] + target[2] * target[2]), 1e-9);
    }
    // 64 mm IPD at 0.5 m straight ahead: 2 atan(32/500) = 7.32 degrees.
    const auto v = vergence(*p, normalize({0.032, 0, 0.5}), normalize({-0.032, 0, 0.5}));
    EXPECT_NEAR(v.vergence_deg, 2 * std::atan(0.032 / 0.5) / kDeg, 1e-9);
}

TEST(Vergence, ParallelAndDivergingRaysHaveNoPoint) {
    auto p = find_profile("oculus-dk2-patney");
    ASSERT_TRUE(p.ok());
    EXPECT_FALSE(vergence(*p, {0, 0, 1}, {0, 0, 1}).valid);
    EXPECT_FALSE(vergence(*p, normalize({-0.1, 0, 1}), normalize({0.1, 0, 1})).valid);
    EXPECT_FALSE(vergence(*p, {0, 0, 0}, {0, 0, 1}).valid);
    EXPECT_FALSE(vergence(*p, {NAN, 0, 1}, {0, 0, 1}).valid);
}

TEST(Vergence, SkewRaysGiveTheMidpointAndTheMissDistance) {
    // Left ray along z at y = 0, right ray crossing it 1 cm lower.
    const auto v = vergence({-0.032, 0, 0}, normalize({0.032, 0, 0.5}), {0.032, 0.01, 0},
                            normalize({-0.032, 0, 0.5}));
    ASSERT_TRUE(v.valid);
    EXPECT_NEAR(v.miss_m, 0.01, 1e-9);
    EXPECT_NEAR(v.point_m[1], 0.005, 1e-9);
    EXPECT_NEAR(v.point_m[2], 0.5, 1e-9);
}

// Found by tests/fuzz/fuzz_daemon_config: a name past NAME_MAX made std::filesystem throw
// (ENAMETOOLONG) out of the config parser.
TEST(DisplayProfiles, ANameTooLongForAFileIsAnUnknownProfile) {
    const auto p = find_profile(std::string(300, 'g'));
    ASSERT_FALSE(p.ok());
    EXPECT_NE(p.error().message.find("unknown display profile"), std::string::npos)
        << p.error().message;
}

TEST(DisplayProfiles, InvalidProfilesAreRejectedWithTheReason) {
    auto r = parse_profile("name = 'x'\nkind = 'tv'\n", "t");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("kind"), std::string::npos);
    r = parse_profile("kind = 'monitor'\n", "t");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("'name'"), std::string::npos);
    r = parse_profile("name='m'\nkind='monitor'\nwidth_px=10\nheight_px=10\nwidth_m=0.5\n", "t");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("distance_m"), std::string::npos);
    const char* hmd = R"(name = "h"
kind = "hmd"
[left]
width_px = 1000
height_px = 1000
fov_left_deg = 45
fov_right_deg = 45
fov_up_deg = 95
fov_down_deg = 45
[right]
width_px = 1000
height_px = 1000
fov_left_deg = 45
fov_right_deg = 45
fov_up_deg = 45
fov_down_deg = 45
)";
    r = parse_profile(hmd, "t");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("[left]"), std::string::npos);
    // A declared pixels_per_degree that contradicts the geometry is caught.
    r = parse_profile(
        "name='m'\nkind='monitor'\nwidth_px=1920\nheight_px=1080\nwidth_m=0.531\n"
        "height_m=0.299\ndistance_m=0.6\npixels_per_degree=50\n",
        "t");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("pixels_per_degree"), std::string::npos);
    r = parse_profile("name = [", "t");
    EXPECT_FALSE(r.ok());
    auto missing = find_profile("no-such-profile");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("oculus-dk2-patney"), std::string::npos);
}

}  // namespace
