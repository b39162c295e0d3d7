// Cameras per frame (core/animation.h, core/camera.h): --frames lists, orbits, keyframe paths,
// fitting to the data, and the camera basis and rays the GPU shaders mirror.
#include "core/animation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/error.h"

namespace tc {
namespace {

std::string frameListError(const std::string& spec, int frameCount) {
    try {
        parseFrameList(spec, frameCount);
    } catch (const InputError& e) {
        return e.what();
    }
    return "<no error>";
}

void expectNear(const glm::vec3& a, const glm::vec3& b, float tolerance) {
    EXPECT_NEAR(a.x, b.x, tolerance) << "x";
    EXPECT_NEAR(a.y, b.y, tolerance) << "y";
    EXPECT_NEAR(a.z, b.z, tolerance) << "z";
}

// ---- --frames --------------------------------------------------------------------------------

TEST(Animation, FrameListInclusiveRange) {
    std::vector<int> frames = parseFrameList("0..99", 100);
    ASSERT_EQ(frames.size(), 100u);
    EXPECT_EQ(frames.front(), 0);
    EXPECT_EQ(frames.back(), 99);
}

TEST(Animation, FrameListRangeWithStep) {
    std::vector<int> frames = parseFrameList("0..99:5", 100);
    ASSERT_EQ(frames.size(), 20u);
    for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(frames[i], int(5 * i));
    EXPECT_EQ(parseFrameList("1..10:4", 11), (std::vector<int>{1, 5, 9}));
}

TEST(Animation, FrameListOfSinglesAndRangesIsSortedAndUnique) {
    EXPECT_EQ(parseFrameList("3,7,12..20", 21), (std::vector<int>{3, 7, 12, 13, 14, 15, 16, 17, 18, 19, 20}));
    EXPECT_EQ(parseFrameList("5,1..3,2", 6), (std::vector<int>{1, 2, 3, 5}));
}

TEST(Animation, EmptyFrameListMeansAllFrames) {
    EXPECT_EQ(parseFrameList("", 4), (std::vector<int>{0, 1, 2, 3}));
    EXPECT_EQ(parseFrameList("all", 3), (std::vector<int>{0, 1, 2}));
}

TEST(Animation, FrameListErrorsSayWhatIsWrong) {
    EXPECT_EQ(frameListError("0..100", 100), "--frames 0..100: frame 100 is outside the animation's frames 0..99");
    EXPECT_EQ(frameListError("5", 1), "--frames 5: frame 5 is outside the animation's frames 0..0");
    EXPECT_EQ(frameListError("9..3", 10), "--frames 9..3: range 9..3 ends before it starts");
    EXPECT_EQ(frameListError("abc", 10),
              "--frames abc: expected a frame number, got \"abc\" (syntax: 0..99, 0..99:5, 3,7,12..20)");
    EXPECT_EQ(frameListError("1,,2", 10),
              "--frames 1,,2: expected a frame number, got \"\" (syntax: 0..99, 0..99:5, 3,7,12..20)");
    EXPECT_EQ(frameListError("-1", 10),
              "--frames -1: expected a frame number, got \"-1\" (syntax: 0..99, 0..99:5, 3,7,12..20)");
    EXPECT_EQ(frameListError("0..9:0", 10), "--frames 0..9:0: step must be >= 1");
    EXPECT_EQ(frameListError("0..9:x", 10),
              "--frames 0..9:x: expected a frame number, got \"x\" (syntax: 0..99, 0..99:5, 3,7,12..20)");
    EXPECT_EQ(frameListError("12345678901", 10), "--frames 12345678901: frame number \"12345678901\" is too large");
}

// ---- orbit -----------------------------------------------------------------------------------

AnimationSpec orbit(int frames, glm::vec3 axis, float degrees) {
    AnimationSpec a;
    a.type = AnimationSpec::Type::Orbit;
    a.frames = frames;
    a.axis = axis;
    a.degrees = degrees;
    return a;
}

TEST(Animation, OrbitFrameZeroIsTheBaseCamera) {
    Camera base;
    base.eye = {1, 2, 5};
    base.target = {1, 0, 0};
    Camera c = cameraAtFrame(orbit(36, {0, 1, 0}, 360), base, 0);
    expectNear(c.eye, base.eye, 1e-6f);
    expectNear(c.target, base.target, 0);
    expectNear(c.up, base.up, 1e-6f);
}

TEST(Animation, OrbitQuarterTurnRotatesTheEyeByNinetyDegreesAboutTheTarget) {
    Camera base;
    base.target = {1, 0.5f, -2};
    base.eye = base.target + glm::vec3(0, 0.7f, 4);
    const int frames = 40;
    Camera c = cameraAtFrame(orbit(frames, {0, 1, 0}, 360), base, frames / 4);
    glm::vec3 before = base.eye - base.target, after = c.eye - c.target;
    EXPECT_EQ(c.target, base.target);
    EXPECT_NEAR(glm::length(after), glm::length(before), 1e-5f);
    // About +y by +90 degrees (right-handed): +z goes to +x; the height along the axis is kept.
    expectNear(after, {4, 0.7f, 0}, 1e-5f);
    glm::vec2 b{before.x, before.z}, a{after.x, after.z};
    EXPECT_NEAR(glm::dot(a, b), 0.0f, 1e-5f);
    expectNear(c.up, base.up, 1e-6f);  // up along the axis stays
}

TEST(Animation, OrbitRotatesUpWithTheEye) {
    Camera base;
    base.eye = {0, 0, 3};
    base.up = {0, 1, 0};
    Camera c = cameraAtFrame(orbit(4, {0, 0, 1}, 360), base, 1);  // about the view axis
    expectNear(c.eye, base.eye, 1e-6f);
    expectNear(c.up, {-1, 0, 0}, 1e-6f);
}

TEST(Animation, NoAnimationReturnsTheBaseCamera) {
    Camera base;
    base.eye = {4, 5, 6};
    Camera c = cameraAtFrame(AnimationSpec{}, base, 17);
    EXPECT_EQ(c.eye, base.eye);
}

// ---- keyframes -------------------------------------------------------------------------------

AnimationSpec keyframes(const std::vector<Keyframe>& keys) {
    AnimationSpec a;
    a.type = AnimationSpec::Type::Keyframes;
    a.keys = keys;
    a.frames = keys.back().frame + 1;
    return a;
}

const std::vector<Keyframe> kKeys = {
    {0, {0, 0, 5}, {0, 0, 0}, {0, 1, 0}},
    {10, {5, 1, 0}, {0, 0.5f, 0}, {0, 1, 0}},
    {40, {0, 2, -5}, {1, 0, 0}, {0, 1, 0}},
    {50, {-5, 0, 0}, {0, 0, 0}, {0, 1, 0}},
};

TEST(Animation, KeyframeFramesReproduceTheKeysExactly) {
    AnimationSpec a = keyframes(kKeys);
    Camera base;
    base.fovYDeg = 50;
    for (const Keyframe& k : kKeys) {
        Camera c = cameraAtFrame(a, base, k.frame);
        EXPECT_EQ(c.eye, k.eye) << "frame " << k.frame;
        EXPECT_EQ(c.target, k.target) << "frame " << k.frame;
        EXPECT_EQ(c.up, k.up) << "frame " << k.frame;
        EXPECT_EQ(c.fovYDeg, 50.0f);  // what keys do not set comes from the base camera
    }
}

TEST(Animation, KeyframesAreHeldBeforeTheFirstAndAfterTheLastKey) {
    std::vector<Keyframe> keys = kKeys;
    for (auto& k : keys) k.frame += 5;
    AnimationSpec a = keyframes(keys);
    EXPECT_EQ(cameraAtFrame(a, Camera{}, 0).eye, keys.front().eye);
    EXPECT_EQ(cameraAtFrame(a, Camera{}, 4).eye, keys.front().eye);
    EXPECT_EQ(cameraAtFrame(a, Camera{}, 56).eye, keys.back().eye);
    EXPECT_EQ(cameraAtFrame(a, Camera{}, 1000).target, keys.back().target);
}

TEST(Animation, KeyframePathHasNoVelocityJumpAtInteriorKeys) {
    // C1 in frame time, also where the key spacing changes from 100 to 300 frames: the second
    // difference across a key is about the mean of the accelerations on its two sides (it would
    // be the velocity jump, ~50x larger here, for a spline that is C1 only in its per-segment
    // parameter: that one changes speed by the spacing ratio at the key).
    AnimationSpec a = keyframes({{0, {0, 0, 5}, {0, 0, 0}, {0, 1, 0}},
                                 {100, {5, 1, 0}, {0, 0.5f, 0}, {0, 1, 0}},
                                 {400, {0, 2, -5}, {1, 0, 0}, {0, 1, 0}},
                                 {500, {-5, 0, 0}, {0, 0, 0}, {0, 1, 0}}});
    for (int key : {100, 400}) {
        for (auto part : {&Camera::eye, &Camera::target}) {
            auto at = [&](int f) { return cameraAtFrame(a, Camera{}, f).*part; };
            auto second = [&](int f) { return glm::length(at(f + 1) - 2.0f * at(f) + at(f - 1)); };
            float inside = std::max(second(key - 1), second(key + 1));
            EXPECT_LE(second(key), 1.5f * inside + 1e-5f)
                << "key at frame " << key << ": across " << second(key) << ", beside " << inside;
        }
    }
}

// Uniform Catmull-Rom in the segment parameter t (the textbook form).
glm::vec3 uniformCatmullRom(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3, float t) {
    float t2 = t * t, t3 = t2 * t;
    return 0.5f * ((2.0f * p1) + (-p0 + p2) * t + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * t2 +
                   (-p0 + 3.0f * p1 - 3.0f * p2 + p3) * t3);
}

TEST(Animation, EvenlySpacedKeyframesFollowUniformCatmullRomWithRepeatedEnds) {
    const std::vector<Keyframe> keys = {{0, {0, 0, 5}, {0, 0, 0}, {0, 1, 0}},
                                        {8, {5, 1, 0}, {0, 0.5f, 0}, {0, 1, 0}},
                                        {16, {0, 2, -5}, {1, 0, 0}, {0, 1, 0}},
                                        {24, {-5, 0, 0}, {0, 0, 0}, {0, 1, 0}}};
    AnimationSpec a = keyframes(keys);
    for (int f = 0; f <= 24; ++f) {
        std::size_t i = std::min<std::size_t>(std::size_t(f / 8), 2);
        float t = float(f - keys[i].frame) / 8.0f;
        glm::vec3 expected = uniformCatmullRom(keys[i == 0 ? 0 : i - 1].eye, keys[i].eye, keys[i + 1].eye,
                                               keys[std::min<std::size_t>(i + 2, 3)].eye, t);
        expectNear(cameraAtFrame(a, Camera{}, f).eye, expected, 1e-5f);
    }
}

TEST(Animation, KeyframeUpIsUnitLengthBetweenKeys) {
    AnimationSpec a = keyframes({{0, {0, 0, 5}, {0, 0, 0}, {0, 1, 0}}, {10, {5, 0, 0}, {0, 0, 0}, {1, 1, 0}}});
    for (int f = 1; f < 10; ++f) EXPECT_NEAR(glm::length(cameraAtFrame(a, Camera{}, f).up), 1.0f, 1e-5f);
}

TEST(Animation, TwoKeyframesWithUniformSpacingMatchCatmullRomWithClampedEnds) {
    // With the end keys repeated, the midpoint of a Catmull-Rom segment is the chord's midpoint.
    AnimationSpec a = keyframes({{0, {0, 0, 4}, {0, 0, 0}, {0, 1, 0}}, {10, {4, 0, 0}, {0, 0, 0}, {0, 1, 0}}});
    expectNear(cameraAtFrame(a, Camera{}, 5).eye, {2, 0, 2}, 1e-5f);
}

// ---- fitCamera -------------------------------------------------------------------------------

Bounds box(glm::vec3 lo, glm::vec3 hi) {
    Bounds b;
    b.extend(lo);
    b.extend(hi);
    return b;
}

// Half the angle the bounding sphere subtends from the eye.
float angularRadius(const Camera& c, const Bounds& b) {
    return std::asin(b.radius() / glm::length(c.eye - b.center()));
}

TEST(Animation, FitCameraFitsTheBoundingSphereInBothFieldsOfView) {
    const Bounds b = box({-1, 0, 2}, {3, 1, 4});
    for (float aspect : {0.5f, 1.0f, 16.0f / 9.0f}) {
        for (float fov : {10.0f, 35.0f, 90.0f}) {
            CameraSpec spec;
            spec.fit = true;
            spec.camera.eye = {2, 3, 10};
            spec.camera.target = {0, 0, 0};
            spec.camera.fovYDeg = fov;
            Camera c = fitCamera(spec, b, aspect);
            EXPECT_EQ(c.target, b.center());
            // The view direction given is kept.
            expectNear(glm::normalize(c.eye - c.target), glm::normalize(spec.camera.eye - spec.camera.target), 1e-5f);
            float halfY = glm::radians(fov) / 2;
            float halfX = std::atan(std::tan(halfY) * aspect);
            float angle = angularRadius(c, b);
            EXPECT_LE(angle, halfY) << "aspect " << aspect << " fov " << fov;
            EXPECT_LE(angle, halfX) << "aspect " << aspect << " fov " << fov;
            // ... and fills the smaller one up to the 3 % margin.
            EXPECT_GT(angle, 0.95f * std::min(halfX, halfY)) << "aspect " << aspect << " fov " << fov;
        }
    }
}

TEST(Animation, OrthographicFitCoversTheDiameterInBothDirections) {
    const Bounds b = box({0, 0, 0}, {1, 2, 2});  // diameter 3
    for (float aspect : {0.5f, 1.0f, 2.0f}) {
        CameraSpec spec;
        spec.fit = true;
        spec.camera.projection = Projection::Orthographic;
        spec.camera.orthoHeight = 0.1f;
        Camera c = fitCamera(spec, b, aspect);
        EXPECT_GE(c.orthoHeight, 2 * b.radius()) << "aspect " << aspect;
        EXPECT_GE(c.orthoHeight * aspect, 2 * b.radius()) << "aspect " << aspect;
        // The eye is outside the sphere, so orthographic rays start in front of the data.
        EXPECT_GT(glm::length(c.eye - b.center()), b.radius());
    }
}

TEST(Animation, FitCameraWithoutFitOrWithEmptyBoundsKeepsTheCamera) {
    CameraSpec spec;
    spec.camera.eye = {1, 2, 3};
    EXPECT_EQ(fitCamera(spec, box({0, 0, 0}, {1, 1, 1}), 1.0f).eye, spec.camera.eye);
    spec.fit = true;
    EXPECT_EQ(fitCamera(spec, Bounds{}, 1.0f).eye, spec.camera.eye);
}

// ---- camera basis and rays -------------------------------------------------------------------

Camera obliqueCamera() {
    Camera c;
    c.eye = {3, -2, 5};
    c.target = {0.5f, 1, -1};
    c.up = {0.2f, 1, 0.1f};  // not orthogonal to the view direction
    return c;
}

TEST(Animation, CameraBasisIsRightHandedAndOrthonormal) {
    Camera c = obliqueCamera();
    glm::vec3 f = c.forward(), r = c.right(), u = c.trueUp();
    EXPECT_NEAR(glm::length(f), 1, 1e-6f);
    EXPECT_NEAR(glm::length(r), 1, 1e-6f);
    EXPECT_NEAR(glm::length(u), 1, 1e-6f);
    EXPECT_NEAR(glm::dot(f, r), 0, 1e-6f);
    EXPECT_NEAR(glm::dot(f, u), 0, 1e-6f);
    EXPECT_NEAR(glm::dot(r, u), 0, 1e-6f);
    expectNear(glm::cross(r, u), -f, 1e-6f);  // camera looks down -z of (r, u, -f)
    EXPECT_GT(glm::dot(u, c.up), 0.0f);       // trueUp is on the side of the given up
    expectNear(f, glm::normalize(c.target - c.eye), 1e-6f);
}

TEST(Animation, CameraUpParallelToTheViewStillGivesAnOrthonormalBasis) {
    Camera c;
    c.eye = {0, 5, 0};
    c.target = {0, 0, 0};
    c.up = {0, 1, 0};
    glm::vec3 r = c.right(), u = c.trueUp();
    EXPECT_NEAR(glm::length(r), 1, 1e-6f);
    EXPECT_NEAR(glm::dot(r, u), 0, 1e-6f);
    EXPECT_NEAR(glm::dot(c.forward(), u), 0, 1e-6f);
}

TEST(Animation, CameraCentrePixelRayPointsAlongForward) {
    Camera c = obliqueCamera();
    // Odd sizes have a centre pixel; even sizes a centre between pixels (px = w/2 - 0.5).
    for (auto [w, h] : {std::pair{33, 17}, std::pair{64, 48}}) {
        Ray ray = pixelRay(c, w, h, 0.5f * float(w) - 0.5f, 0.5f * float(h) - 0.5f);
        expectNear(ray.origin, c.eye, 1e-6f);
        expectNear(ray.dir, c.forward(), 1e-6f);
    }
    c.projection = Projection::Orthographic;
    Ray ray = pixelRay(c, 33, 17, 16, 8);
    expectNear(ray.origin, c.eye, 1e-5f);
    expectNear(ray.dir, c.forward(), 1e-6f);
}

TEST(Animation, CameraPixelRaysSpanTheVerticalFieldOfViewAndRowZeroIsTheTop) {
    Camera c = obliqueCamera();
    c.fovYDeg = 40;
    const int w = 40, h = 30;
    // The top edge of the image (py = -0.5, the upper border of row 0) is fov/2 above forward.
    Ray top = pixelRay(c, w, h, 0.5f * w - 0.5f, -0.5f);
    EXPECT_NEAR(std::acos(glm::dot(top.dir, c.forward())), glm::radians(20.0f), 1e-5f);
    EXPECT_GT(glm::dot(top.dir, c.trueUp()), 0.0f);
    Ray right = pixelRay(c, w, h, float(w) - 0.5f, 0.5f * h - 0.5f);
    EXPECT_GT(glm::dot(right.dir, c.right()), 0.0f);
}

TEST(Animation, CameraWorldToCameraMapsTheEyeToTheOriginAndTheTargetToMinusZ) {
    Camera c = obliqueCamera();
    glm::mat4 m = c.worldToCamera();
    expectNear(glm::vec3(m * glm::vec4(c.eye, 1)), {0, 0, 0}, 1e-5f);
    float distance = glm::length(c.target - c.eye);
    expectNear(glm::vec3(m * glm::vec4(c.target, 1)), {0, 0, -distance}, 1e-5f);
    expectNear(glm::vec3(m * glm::vec4(c.eye + c.right(), 1)), {1, 0, 0}, 1e-5f);
    expectNear(glm::vec3(m * glm::vec4(c.eye + c.trueUp(), 1)), {0, 1, 0}, 1e-5f);
}

}  // namespace
}  // namespace tc
