// JSON scene files (docs/scene-format.md): exact round trips, defaults, and errors that name the
// file and the JSON path of the bad value.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/rows/distance.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/scene/scene_json.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "fixture.hpp"

using namespace cbps;

namespace {

/// A scene with every kind of thing the format holds: a sphere and a box with velocities, an
/// inertia override, a static body, and constraints to the world, between bodies, and to the
/// static body. Nothing in it is a round number, so the writer must keep every bit.
Scene mixed_scene() {
  Scene scene;
  scene.name = "mixed";
  scene.parameters = {{"n", "3"}, {"alpha", "0.1"}};  // not in alphabetical order
  scene.duration = 2.5;
  scene.world.gravity = Vec3(0.1, -9.80665, 1.0 / 3.0);
  scene.world.dt = 1.0 / 300.0;
  scene.world.beta = 0.15;
  scene.solver.method = Method::MatrixFree;
  scene.solver.max_iterations = 37;
  scene.solver.tolerance = 1e-9;
  scene.solver.delta_tolerance = 1e-12;
  scene.solver.relaxation = 0.7;
  scene.solver.warm = 0.85;
  scene.solver.warm_friction = 0.0;
  scene.solver.contacts_first = true;

  Body ball;
  ball.name = "ball";
  ball.shape.kind = Shape::Kind::Sphere;
  ball.shape.radius = 0.02;
  set_mass(ball, 0.1);
  ball.x = Vec3(0.3, -0.2, 0.1);
  ball.q = axis_angle_quaternion(Vec3(0.3, 0.1, -0.2));
  ball.set_velocity(Vec3(1.0 / 3.0, 0.7, -0.1), Vec3(0.2, 1.0 / 7.0, 3.0));

  Body box;
  box.name = "box";
  box.shape.kind = Shape::Kind::Box;
  box.shape.half_extents = Vec3(0.1, 0.2, 0.3);
  set_mass(box, 2.5);
  box.I_body << 0.11, 0.01, -0.002,  //
      0.01, 0.09, 0.003,             //
      -0.002, 0.003, 0.05;
  box.I_body_inv = box.I_body.inverse();
  box.x = Vec3(0.1, -0.6, 0.0);
  box.q = axis_angle_quaternion(Vec3(-1.1, 0.4, 2.0));
  box.set_velocity(Vec3(0.0, -0.25, 0.125), Vec3(0.0, 0.0, 0.0));

  Body floor;
  floor.name = "floor";
  floor.is_static = true;
  floor.shape.kind = Shape::Kind::Box;
  floor.shape.half_extents = Vec3(5.0, 0.1, 5.0);
  floor.x = Vec3(0.0, -1.0, 0.0);

  scene.bodies = {ball, box, floor};
  scene.distances = {
      {"hang", -1, 0, Vec3(0.0, 1.0, 0.0), Vec3(0.0, 0.02, 0.0), 1.2},
      {"link", 0, 1, Vec3(0.0, -0.02, 0.0), Vec3(0.1, 0.2, 0.3), 0.4},
      {"tie", 1, 2, Vec3(-0.1, -0.2, 0.0), Vec3(0.0, 0.1, 0.0), 1.0 / 3.0},
  };
  return scene;
}

/// Every field, compared for exact equality.
void check_same(const Scene& got, const Scene& want) {
  CHECK(got.name == want.name);
  CHECK(got.parameters == want.parameters);
  CHECK(got.duration == want.duration);
  CHECK(got.world.gravity == want.world.gravity);
  CHECK(got.world.dt == want.world.dt);
  CHECK(got.world.beta == want.world.beta);
  CHECK(got.world.push == want.world.push);
  CHECK(got.world.integrator == want.world.integrator);
  CHECK(got.world.scheme.kind == want.world.scheme.kind);
  CHECK(got.world.scheme.substeps == want.world.scheme.substeps);
  CHECK(got.world.scheme.contact_hertz == want.world.scheme.contact_hertz);
  CHECK(got.world.scheme.contact_damping_ratio == want.world.scheme.contact_damping_ratio);
  CHECK(got.world.scheme.joint_hertz == want.world.scheme.joint_hertz);
  CHECK(got.world.scheme.joint_damping_ratio == want.world.scheme.joint_damping_ratio);
  CHECK(got.world.scheme.max_push_speed == want.world.scheme.max_push_speed);
  CHECK(got.world.scheme.compliance == want.world.scheme.compliance);
  CHECK(got.world.scheme.speculative_distance == want.world.scheme.speculative_distance);
  CHECK(got.world.mu == want.world.mu);
  CHECK(got.world.friction == want.world.friction);
  CHECK(got.world.restitution == want.world.restitution);
  CHECK(got.world.restitution_threshold == want.world.restitution_threshold);
  CHECK(got.world.contact_margin == want.world.contact_margin);
  CHECK(got.world.contact_persistence == want.world.contact_persistence);
  CHECK(got.solver.method == want.solver.method);
  CHECK(got.solver.max_iterations == want.solver.max_iterations);
  CHECK(got.solver.tolerance == want.solver.tolerance);
  CHECK(got.solver.delta_tolerance == want.solver.delta_tolerance);
  CHECK(got.solver.relaxation == want.solver.relaxation);
  CHECK(got.solver.warm == want.solver.warm);
  CHECK(got.solver.warm_friction == want.solver.warm_friction);
  CHECK(got.solver.contacts_first == want.solver.contacts_first);
  CHECK(got.solver.split_islands == want.solver.split_islands);
  REQUIRE(got.bodies.size() == want.bodies.size());
  for (std::size_t i = 0; i < want.bodies.size(); ++i) {
    const Body& g = got.bodies[i];
    const Body& w = want.bodies[i];
    INFO("body " << i << " (" << w.name << ")");
    CHECK(g.name == w.name);
    CHECK(g.shape.kind == w.shape.kind);
    if (w.shape.kind == Shape::Kind::Sphere)
      CHECK(g.shape.radius == w.shape.radius);
    else
      CHECK(g.shape.half_extents == w.shape.half_extents);
    CHECK(g.is_static == w.is_static);
    CHECK(g.collides == w.collides);
    CHECK(g.m == w.m);
    CHECK(g.I_body == w.I_body);
    CHECK(g.I_body_inv == w.I_body_inv);
    CHECK(g.x == w.x);
    CHECK(g.q.coeffs() == w.q.coeffs());
    CHECK(g.p == w.p);
    CHECK(g.l == w.l);
  }
  REQUIRE(got.distances.size() == want.distances.size());
  for (std::size_t k = 0; k < want.distances.size(); ++k) {
    const DistanceConstraint& g = got.distances[k];
    const DistanceConstraint& w = want.distances[k];
    INFO("constraint " << k << " (" << w.name << ")");
    CHECK(g.name == w.name);
    CHECK(g.a == w.a);
    CHECK(g.b == w.b);
    CHECK(g.anchor_a == w.anchor_a);
    CHECK(g.anchor_b == w.anchor_b);
    CHECK(g.length == w.length);
  }
}

/// A scene with contacts: every contact setting away from its default, a tilted ground plane, a
/// box that collides and a sphere that does not. Nothing in it is a round number.
Scene contact_scene() {
  Scene scene;
  scene.name = "contacts";
  scene.world.push = PushMode::Improved;
  scene.world.integrator = Integrator::Gyroscopic;
  scene.world.scheme.kind = Scheme::SoftStep;
  scene.world.scheme.substeps = 7;
  scene.world.scheme.contact_hertz = 27.5;
  scene.world.scheme.contact_damping_ratio = 8.25;
  scene.world.scheme.joint_hertz = 55.5;
  scene.world.scheme.joint_damping_ratio = 1.75;
  scene.world.scheme.max_push_speed = 2.5;
  scene.world.scheme.speculative_distance = 0.0125;
  scene.world.mu = 0.35;
  scene.world.friction = FrictionLaw::CoulombBox;
  scene.world.restitution = 0.45;
  scene.world.restitution_threshold = 1.0 / 30.0;
  scene.world.contact_margin = 0.004;
  scene.world.contact_persistence = 0.03;
  scene.solver.split_islands = false;

  Body ground;
  ground.name = "ground";
  ground.shape.kind = Shape::Kind::Plane;
  ground.is_static = true;
  ground.x = Vec3(0.0, -0.05, 0.0);
  ground.q = axis_angle_quaternion(Vec3(0.0, 0.0, 0.1));

  Body box;
  box.name = "box";
  box.shape.kind = Shape::Kind::Box;
  box.shape.half_extents = Vec3(0.1, 0.1, 0.1);
  set_mass(box, 1.3);
  box.x = Vec3(0.2, 0.07, 0.0);
  box.set_velocity(Vec3(0.0, -1.0 / 3.0, 0.0), Vec3(0.0, 0.0, 0.0));

  Body ghost;
  ghost.name = "ghost";
  ghost.collides = false;
  ghost.shape.radius = 0.07;
  set_mass(ghost, 0.3);
  ghost.x = Vec3(0.2, 0.1, 0.0);

  scene.bodies = {ground, box, ghost};
  return scene;
}

/// How many times `word` occurs in `text`.
std::size_t count(const std::string& text, const std::string& word) {
  std::size_t n = 0;
  for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) ++n;
  return n;
}

/// A scene with one body given by its JSON fields (inside the braces).
std::string one_body(const std::string& fields) {
  return R"({"bodies": [{"shape": {"type": "sphere", "radius": 0.1})" +
         (fields.empty() ? "" : ", " + fields) + "}]}";
}

/// Two bodies "a" (movable, at x = 1) and "s" (static), and the given constraints.
std::string two_bodies(const std::string& constraints) {
  return R"({"bodies": [
    {"name": "a", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1, "position": [1, 0, 0]},
    {"name": "s", "shape": {"type": "sphere", "radius": 0.1}, "static": true}],
   "constraints": [)" +
         constraints + "]}";
}

}  // namespace

TEST_CASE("scene_to_json then parse_scene gives back every field bit for bit", "[scene_json]") {
  const Scene scene = mixed_scene();
  const std::string text = scene_to_json(scene);
  INFO(text);
  const Scene back = parse_scene(text, "written.json");
  check_same(back, scene);
  // Written again, the text is the same: writing is a function of the scene alone.
  CHECK(scene_to_json(back) == text);
}

TEST_CASE("a shape too small for its own inertia keeps the inertia given and round-trips",
          "[scene_json]") {
  // r = 1e-320 m: the solid sphere's I = 0.4 m r² underflows to 0 and has no inverse, so the
  // reader needs the "inertia" given, and the writer must write it (found by fuzz_scene_json).
  const Scene scene = parse_scene(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1e-320},
                                    "mass": 2, "inertia": [2, 3, 4]}]})",
                                  "tiny.json");
  REQUIRE(scene.bodies.size() == 1);
  CHECK(scene.bodies[0].I_body_inv(2, 2) == 0.25);
  const std::string text = scene_to_json(scene);
  INFO(text);
  CHECK(count(text, "\"inertia\"") == 1);
  check_same(parse_scene(text, "written.json"), scene);
  // Without the inertia the same body is refused: its solid's inverse is not finite.
  CHECK_THROWS_AS(parse_scene(R"({"bodies": [{"shape": {"type": "sphere", "radius": 1e-320},
                                   "mass": 2}]})",
                              "tiny.json"),
                  InputError);
}

TEST_CASE("planes, collides and the contact settings (4, 5.4, 8.1, 8.2) round-trip bit for bit",
          "[scene_json]") {
  const Scene scene = contact_scene();
  const std::string text = scene_to_json(scene);
  INFO(text);
  const Scene back = parse_scene(text, "written.json");
  check_same(back, scene);
  CHECK(scene_to_json(back) == text);
  // "collides" is written only for the one body that does not collide; a plane has no mass.
  CHECK(count(text, "\"collides\"") == 1);
  CHECK(count(text, "\"collides\": false") == 1);
  CHECK(count(text, "\"mass\"") == 2);
  // Coulomb's cone and its law (docs/cones.md): "cone" is written only with friction "cone".
  CHECK(count(text, "\"cone\"") == 0);
  Scene cone = scene;
  cone.world.friction = FrictionLaw::Relaxation;
  const std::string cone_text = scene_to_json(cone);
  CHECK(count(cone_text, "\"cone\": \"ccp\"") == 1);
  check_same(parse_scene(cone_text, "cone.json"), cone);
}

TEST_CASE("a plane, a box, contact settings and collides = false read to the values written",
          "[scene_json]") {
  // The plane is turned 90° about x: its outward normal R (0, 1, 0) is then +z.
  const Scene scene = parse_scene(R"({
      "world": {"push": "improved", "integrator": "midpoint", "scheme": "xpbd",
                "compliance": 1e-6, "mu": 0.5, "friction": "coulomb",
                "restitution": 0.25,
                "restitution_threshold": 0.2, "contact_margin": 0.01},
      "solver": {"split_islands": false},
      "bodies": [
        {"name": "wall", "shape": {"type": "plane"}, "static": true, "position": [0, 0, -1],
         "orientation": [0.7071067811865476, 0.7071067811865476, 0, 0]},
        {"name": "box", "shape": {"type": "box", "half_extents": [0.1, 0.2, 0.3]}, "mass": 2,
         "collides": false}]})",
                                  "scene.json");
  CHECK(scene.world.push == PushMode::Improved);
  CHECK(scene.world.integrator == Integrator::Midpoint);
  CHECK(scene.world.scheme.kind == Scheme::Xpbd);
  CHECK(scene.world.scheme.substeps == kSchemeSubsteps);  // named without substeps: 4
  CHECK(scene.world.scheme.compliance == 1e-6);
  CHECK(scene.world.mu == 0.5);
  CHECK(scene.world.friction == FrictionLaw::CoulombBox);
  CHECK(scene.world.restitution == 0.25);
  CHECK(scene.world.restitution_threshold == 0.2);
  CHECK(scene.world.contact_margin == 0.01);
  CHECK_FALSE(scene.solver.split_islands);
  CHECK(scene.world.beta == 0.2);  // untouched settings keep their defaults
  REQUIRE(scene.bodies.size() == 2);
  const Body& wall = scene.bodies[0];
  CHECK(wall.shape.kind == Shape::Kind::Plane);
  CHECK(wall.is_static);
  CHECK(wall.collides);
  CHECK(wall.m == 1.0);  // the unused default of a static body
  CHECK(wall.x == Vec3(0.0, 0.0, -1.0));
  const Vec3 n = wall.R() * Vec3::UnitY();
  CHECK((n - Vec3(0.0, 0.0, 1.0)).norm() < 1e-15);
  const Body& box = scene.bodies[1];
  CHECK(box.shape.kind == Shape::Kind::Box);
  CHECK(box.shape.half_extents == Vec3(0.1, 0.2, 0.3));
  CHECK(box.m == 2.0);
  CHECK_FALSE(box.is_static);
  CHECK_FALSE(box.collides);
  CHECK_FALSE(scene.has_contact_pairs());  // the only movable body does not collide
}

TEST_CASE("contact settings default to push original, mu 0, paper friction, no bounce",
          "[scene_json]") {
  const Scene scene = parse_scene(one_body(R"("mass": 1)"), "scene.json");
  CHECK(scene.world.push == PushMode::Original);
  CHECK(scene.world.integrator == Integrator::Paper);
  CHECK(scene.world.mu == 0.0);
  CHECK(scene.world.friction == FrictionLaw::PaperBox);
  CHECK(scene.world.restitution == 0.0);
  CHECK(scene.world.restitution_threshold == 0.1);
  CHECK(scene.world.contact_margin == 0.0);
  CHECK(scene.solver.split_islands);
  CHECK(scene.bodies.at(0).collides);
}

TEST_CASE("every built-in scene, written as JSON, reads back bit for bit", "[scene_json]") {
  for (const BuiltinScene& builtin : builtin_scenes()) {
    INFO("built-in scene " << builtin.name);
    const Scene scene = make_builtin_scene(builtin.name, {});
    check_same(parse_scene(scene_to_json(scene), builtin.name + ".json"), scene);
  }
}

TEST_CASE("example scenes in scenes/ parse and round-trip", "[scene_json]") {
  const Scene chain = read_scene_file(CBPS_SOURCE_DIR "/scenes/two-link-chain.json");
  CHECK(chain.name == "two-link-chain");
  CHECK(chain.world.dt == 1.0 / 240.0);
  REQUIRE(chain.bodies.size() == 2);
  REQUIRE(chain.distances.size() == 2);
  CHECK(chain.distances[0].a == -1);
  CHECK(chain.distances[1].b == 1);
  for (const DistanceConstraint& dc : chain.distances)
    CHECK(std::abs(distance_violation(dc, chain.bodies)) < 1e-15);  // starts on the links
  check_same(parse_scene(scene_to_json(chain), "chain"), chain);

  const Scene box = read_scene_file(CBPS_SOURCE_DIR "/scenes/spinning-box.json");
  CHECK(box.name == "spinning-box");
  CHECK(box.world.gravity.isZero(0.0));
  REQUIRE(box.bodies.size() == 1);
  CHECK(box.bodies[0].m == Approx(500.0 * 0.6 * 0.4 * 0.2).epsilon(1e-14));
  CHECK((box.bodies[0].omega() - Vec3(0.01, 5.0, 0.01)).norm() < 1e-14);
  CHECK(box.distances.empty());
  check_same(parse_scene(scene_to_json(box), "box"), box);

  const Scene resting = read_scene_file(CBPS_SOURCE_DIR "/scenes/box-on-plane.json");
  CHECK(resting.name == "box-on-plane");
  CHECK(resting.world.mu == 0.5);
  CHECK(resting.world.push == PushMode::Improved);
  REQUIRE(resting.bodies.size() == 2);
  const Body& ground = resting.bodies[0];
  CHECK(ground.shape.kind == Shape::Kind::Plane);
  CHECK(ground.is_static);
  CHECK(ground.x.isZero(0.0));
  const Body& cube = resting.bodies[1];
  CHECK(cube.shape.half_extents == Vec3(0.1, 0.1, 0.1));
  CHECK(cube.m == 1.0);
  CHECK(cube.x == Vec3(0.0, 0.1, 0.0));  // its bottom face on the plane y = 0
  CHECK(resting.has_contact_pairs());
  check_same(parse_scene(scene_to_json(resting), "resting"), resting);
}

TEST_CASE("a missing length defaults to the current distance between the anchors", "[scene_json]") {
  // Body "a" at (1, 0, 0) turned 90° about z: its body-frame anchor (0.5, 0, 0) sits at
  // (1, 0.5, 0) in the world; the world anchor is (0, 0, 2). Distance sqrt(1 + 0.25 + 4).
  const Scene scene = parse_scene(R"({"bodies": [
      {"name": "a", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1,
       "position": [1, 0, 0], "orientation": [0.7071067811865476, 0, 0, 0.7071067811865476]}],
     "constraints": [{"a": "world", "b": "a", "anchor_a": [0, 0, 2], "anchor_b": [0.5, 0, 0]}]})",
                                  "scene.json");
  REQUIRE(scene.distances.size() == 1);
  CHECK(scene.distances[0].length == Approx(std::sqrt(5.25)).epsilon(1e-14));
  CHECK(scene.distances[0].name == "distance0");
  CHECK(std::abs(distance_violation(scene.distances[0], scene.bodies)) < 1e-15);
}

TEST_CASE("density gives mass = density × volume, and the solid's inertia", "[scene_json]") {
  const Scene scene =
      parse_scene(R"({"bodies": [{"shape": {"type": "box", "half_extents": [0.1, 0.2, 0.05]},
                                  "density": 7800}]})",
                  "scene.json");
  const Body& body = scene.bodies.at(0);
  CHECK(body.m == 7800.0 * body.shape.volume());
  CHECK(body.I_body == body.shape.inertia(body.m));
  CHECK(body.name == "body0");
  CHECK(scene.name == "scene");
}

TEST_CASE("velocities become momenta p = m v, l = I omega (3.2)", "[scene_json]") {
  const Scene scene =
      parse_scene(one_body(R"("mass": 2, "inertia": [1, 2, 3], "orientation": [0, 1, 0, 0],
                  "velocity": [1, 2, 3], "angular_velocity": [0.5, -1, 2])"),
                  "scene.json");
  const Body& body = scene.bodies.at(0);
  CHECK(body.p == 2.0 * Vec3(1, 2, 3));
  CHECK(body.I_body == Vec3(1, 2, 3).asDiagonal().toDenseMatrix());
  CHECK((body.omega() - Vec3(0.5, -1, 2)).norm() < 1e-15);
  CHECK((body.l - body.I_world() * Vec3(0.5, -1, 2)).norm() < 1e-15);
}

TEST_CASE("a static body needs no mass and may be a constraint end", "[scene_json]") {
  const Scene scene = parse_scene(two_bodies(R"({"a": "s", "b": 0, "length": 0.5})"), "s.json");
  CHECK(scene.bodies[1].is_static);
  CHECK(scene.bodies[1].m == 1.0);
  CHECK(scene.distances[0].a == 1);
  CHECK(scene.distances[0].b == 0);
  CHECK(scene.distances[0].length == 0.5);
}

TEST_CASE("dt may be a fraction p/q", "[scene_json]") {
  const Scene scene = parse_scene(R"({"world": {"dt": "1/240"}, "bodies": []})", "scene.json");
  CHECK(scene.world.dt == 1.0 / 240.0);
}

TEST_CASE("a scene file's name defaults to its file stem, a missing file is an InputError",
          "[scene_json]") {
  const std::filesystem::path path =
      cbps::test::scratch_dir("unnamed_scene") / "cbps-test-unnamed-scene.json";
  {
    std::ofstream out(path);
    out << R"({"bodies": []})";
  }
  CHECK(read_scene_file(path.string()).name == "cbps-test-unnamed-scene");
  std::filesystem::remove(path);
  const std::string missing = "/nonexistent/dir/scene.json";
  REQUIRE_THROWS_AS(read_scene_file(missing), InputError);
  REQUIRE_THROWS_WITH(read_scene_file(missing), "/nonexistent/dir/scene.json: cannot open");
}

TEST_CASE("bad input is an InputError naming the JSON path and the reason", "[scene_json]") {
  struct BadInput {
    std::string text;
    std::string message;  // expected part of what()
  };
  const auto bad = GENERATE(values<BadInput>({
      // Numbers out of range, wrong types, non-finite values.
      {one_body(R"("mass": -1)"), "scene.json: /bodies/0/mass: must be > 0 (got -1)"},
      {one_body(R"("mass": "heavy")"),
       "scene.json: /bodies/0/mass: expected a number (got string)"},
      {one_body(R"("mass": 1, "position": [0, 1e999, 0])"),
       "scene.json: /bodies/0/position/1: not a finite number"},
      // Finite but out of range (issue 50, item 10): named by what they exceed.
      {one_body(R"("mass": 1, "position": [0, 1e308, 0])"),
       "scene.json: /bodies/0/position: overflows the body's energy"},
      {one_body(R"("mass": 1, "velocity": [1e200, 0, 0])"),
       "scene.json: /bodies/0/velocity: gives a speed of 1e+200 m/s, beyond "
       "/world/divergence_speed (10000 m/s"},
      {one_body(R"("mass": 1, "angular_velocity": [0, 2e4, 0])"),
       "scene.json: /bodies/0/angular_velocity: gives a spin of 20000 rad/s, beyond "
       "/world/divergence_spin"},
      {one_body(R"("mass": 1, "position": [0, 1])"),
       "scene.json: /bodies/0/position: expected an array of 3 numbers (got array of 2)"},
      {R"({"duration": -1, "bodies": []})", "scene.json: /duration: must be > 0 (got -1)"},
      {R"({"world": {"dt": 0}, "bodies": []})", "scene.json: /world/dt: must be > 0 (got 0)"},
      {R"({"world": {"dt": "1/0"}, "bodies": []})",
       R"(scene.json: /world/dt: expected a number or a fraction such as "1/240" (got "1/0"))"},
      {R"({"world": {"gravity": [0, -1e400, 0]}, "bodies": []})",
       "scene.json: /world/gravity/1: not a finite number"},
      {R"({"world": {"beta": 1.5}, "bodies": []})",
       "scene.json: /world/beta: must be in [0, 1] (got 1.5)"},
      {R"({"solver": {"method": "cg"}, "bodies": []})",
       R"(scene.json: /solver/method: unknown method "cg" (valid: pgs, sgs, jacobi, block-pgs, matrix-free, pgs-nesterov, apgd, nncg, pgs-sm, admm, rbgs, shock, direct, active-set, lemke)"},
      {R"({"solver": {"method": "apgd", "parameters": {"grow": 3, "speed": 2}}, "bodies": []})",
       "scene.json: /solver/parameters/speed: unknown parameter for method \"apgd\" (valid: "
       "restart, grow, shrink)"},
      {R"({"solver": {"method": "apgd", "parameters": {"shrink": 1.5}}, "bodies": []})",
       "scene.json: /solver/parameters/shrink: must be a number in (0, 1] (got 1.5)"},
      {R"({"solver": {"method": "admm", "parameters": {"adapt": "sometimes"}}, "bodies": []})",
       "scene.json: /solver/parameters/adapt: must be on or off (got \"sometimes\")"},
      {R"({"solver": {"parameters": {"grow": 3}}, "bodies": []})",
       "scene.json: /solver/parameters/grow: method \"pgs\" has no parameters of its own"},
      {R"({"solver": {"method": "apgd", "parameters": [3]}, "bodies": []})",
       "scene.json: /solver/parameters: expected an object of the method's parameters"},
      {R"({"solver": {"iterations": 0}, "bodies": []})",
       "scene.json: /solver/iterations: must be >= 1 (got 0)"},
      {R"({"solver": {"iterations": 2.5}, "bodies": []})",
       "scene.json: /solver/iterations: expected an integer (got 2.5)"},
      {R"({"solver": {"tolerance": -1}, "bodies": []})",
       "scene.json: /solver/tolerance: must be >= 0 (got -1)"},
      {R"({"solver": {"relaxation": 2}, "bodies": []})",
       "scene.json: /solver/relaxation: must be in (0, 2) (got 2)"},
      {R"({"solver": {"warm_start": "yes"}, "bodies": []})",
       "scene.json: /solver/warm_start: expected true or false (got string)"},
      {R"({"solver": {"warm": 1.5}, "bodies": []})",
       "scene.json: /solver/warm: must be in [0, 1] (got 1.5)"},
      {R"({"solver": {"warm": true}, "bodies": []})",
       "scene.json: /solver/warm: expected a number (got boolean)"},
      {R"({"solver": {"warm_friction": -0.5}, "bodies": []})",
       "scene.json: /solver/warm_friction: must be in [0, 1] (got -0.5)"},
      {R"({"solver": {"warm_start": true, "warm": 0.5}, "bodies": []})",
       "scene.json: /solver/warm_start: give /solver/warm or /solver/warm_start, not both"},
      {R"({"solver": {"contacts_first": "on"}, "bodies": []})",
       "scene.json: /solver/contacts_first: expected true or false (got string)"},
      {R"({"solver": {"method": "jacobi", "contacts_first": true}, "bodies": []})",
       R"(scene.json: /solver/contacts_first: applies to the methods pgs and matrix-free (method is "jacobi"))"},
      {R"({"solver": {"split_islands": 1}, "bodies": []})",
       "scene.json: /solver/split_islands: expected true or false (got number)"},
      // Contact settings.
      {R"({"world": {"mu": -0.1}, "bodies": []})",
       "scene.json: /world/mu: must be >= 0 (got -0.1)"},
      {R"({"world": {"restitution": 1.5}, "bodies": []})",
       "scene.json: /world/restitution: must be in [0, 1] (got 1.5)"},
      {R"({"world": {"restitution_threshold": -1}, "bodies": []})",
       "scene.json: /world/restitution_threshold: must be >= 0 (got -1)"},
      {R"({"world": {"contact_margin": -0.001}, "bodies": []})",
       "scene.json: /world/contact_margin: must be >= 0 (got -0.001)"},
      {R"({"world": {"push": "sometimes"}, "bodies": []})",
       R"(scene.json: /world/push: unknown push mode "sometimes" (valid: original, improved))"},
      {R"({"world": {"integrator": "verlet"}, "bodies": []})",
       R"(scene.json: /world/integrator: unknown integrator "verlet" (valid: paper, gyroscopic, midpoint))"},
      {R"({"world": {"friction": "viscous"}, "bodies": []})",
       R"(scene.json: /world/friction: unknown friction model "viscous" (valid: paper, coulomb, cone))"},
      {R"({"world": {"friction": "cone", "cone": "elliptic"}, "bodies": []})",
       R"(scene.json: /world/cone: unknown cone law "elliptic" (valid: coulomb, ccp))"},
      {R"({"world": {"mu": "high"}, "bodies": []})",
       "scene.json: /world/mu: expected a number (got string)"},
      {R"({"world": {"margin": 0}, "bodies": []})",
       "scene.json: /world/margin: unknown key (valid: gravity, dt, beta, push, integrator, "
       "scheme, substeps,"},
      {R"({"world": {"scheme": "verlet"}, "bodies": []})",
       R"(scene.json: /world/scheme: unknown scheme "verlet" (valid: paper, tgs, soft-step, xpbd))"},
      {R"({"world": {"substeps": 4}, "bodies": []})",
       "scene.json: /world/substeps: needs a scheme that substeps (tgs, soft-step, xpbd), not "
       "paper"},
      {R"({"world": {"scheme": "tgs", "substeps": 0}, "bodies": []})",
       "scene.json: /world/substeps: must be >= 1 (got 0)"},
      {R"({"world": {"scheme": "soft-step", "contact_hertz": -30}, "bodies": []})",
       "scene.json: /world/contact_hertz: must be >= 0 (got -30)"},
      {R"({"parameters": {"n": 3}, "bodies": []})",
       "scene.json: /parameters/n: expected a string (got number)"},
      // Structure: unknown, duplicate and missing keys.
      {one_body(R"("masss": 1)"), "scene.json: /bodies/0/masss: unknown key (valid: name, shape,"},
      {R"({"gravity": [0, 0, 0], "bodies": []})", "scene.json: /gravity: unknown key"},
      {R"({"a/b": 1, "bodies": []})", "scene.json: /a~1b: unknown key"},
      {one_body(R"("mass": 1, "mass": 2)"), "scene.json: /bodies/0/mass: duplicate key"},
      {R"([1, 2])", "scene.json: /: expected an object (got array)"},
      {R"({"bodies": {}})", "scene.json: /bodies: expected an array (got object)"},
      {R"({})", "scene.json: /bodies: missing (required)"},
      {R"({"bodies": [{"mass": 1}]})", "scene.json: /bodies/0/shape: missing (required)"},
      // Shapes, masses, inertia, orientation.
      {R"({"bodies": [{"shape": {"type": "cylinder"}, "mass": 1}]})",
       R"(scene.json: /bodies/0/shape/type: unknown shape type "cylinder" (valid: sphere, box, plane))"},
      {R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "mass": 1},
                      {"shape": {"type": "box", "half_extents": [1, 1, 1]}, "mass": 1},
                      {"shape": {"type": "plane"}}]})",
       "scene.json: /bodies/2/static: a plane must be static"},
      {R"({"bodies": [{"shape": {"type": "plane"}, "static": false, "mass": 1}]})",
       "scene.json: /bodies/0/static: a plane must be static"},
      {R"({"bodies": [{"shape": {"type": "plane"}, "static": true, "mass": 1}]})",
       "scene.json: /bodies/0/mass: a plane has no mass or inertia"},
      {R"({"bodies": [{"shape": {"type": "plane", "radius": 1}, "static": true}]})",
       "scene.json: /bodies/0/shape/radius: unknown key (valid: type)"},
      {one_body(R"("mass": 1, "collides": "no")"),
       "scene.json: /bodies/0/collides: expected true or false (got string)"},
      {R"({"bodies": [{"shape": {"type": "sphere", "radius": 0}, "mass": 1}]})",
       "scene.json: /bodies/0/shape/radius: must be > 0 (got 0)"},
      {R"({"bodies": [{"shape": {"type": "box", "half_extents": [1, 0, 1]}, "mass": 1}]})",
       "scene.json: /bodies/0/shape/half_extents/1: must be > 0 (got 0)"},
      {R"({"bodies": [{"shape": {"type": "sphere", "radius": 1, "half_extents": [1, 1, 1]},
                       "mass": 1}]})",
       "scene.json: /bodies/0/shape/half_extents: unknown key (valid: type, radius)"},
      {one_body(""), "scene.json: /bodies/0: a movable body needs \"mass\""},
      {one_body(R"("mass": 1, "density": 1000)"),
       R"(scene.json: /bodies/0: give "mass" or "density", not both)"},
      {R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "mass": 1},
                      {"shape": {"type": "sphere", "radius": 1}, "mass": 1,
                       "inertia": [[1, 2, 0], [2, 1, 0], [0, 0, 1]]}]})",
       "scene.json: /bodies/1/inertia: not positive definite"},
      {one_body(R"("mass": 1, "inertia": [1, -2, 1])"),
       "scene.json: /bodies/0/inertia: not positive definite"},
      {one_body(R"("mass": 1, "inertia": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])"),
       "scene.json: /bodies/0/inertia: not symmetric"},
      {one_body(R"("mass": 1, "inertia": [1, 2])"),
       "scene.json: /bodies/0/inertia: expected [Ixx, Iyy, Izz] or a 3x3 array"},
      {one_body(R"("mass": 1, "orientation": [2, 0, 0, 0])"),
       "scene.json: /bodies/0/orientation: must be a unit quaternion"},
      {one_body(R"("mass": 1, "velocity": [1, 0, 0], "momentum": [1, 0, 0])"),
       R"(scene.json: /bodies/0: give "velocity" or "momentum", not both)"},
      {one_body(R"("static": true, "velocity": [1, 0, 0])"),
       "scene.json: /bodies/0/velocity: must be zero for a static body"},
      {one_body(R"("name": "world", "mass": 1)"),
       R"(scene.json: /bodies/0/name: "world" is reserved)"},
      {R"({"bodies": [{"name": "b", "shape": {"type": "sphere", "radius": 1}, "mass": 1},
                      {"name": "b", "shape": {"type": "sphere", "radius": 1}, "mass": 1}]})",
       R"(scene.json: /bodies/1/name: duplicate body name "b" (also /bodies/0))"},
      // Constraints.
      {two_bodies(R"({"a": "world", "b": "a", "length": 0})"),
       "scene.json: /constraints/0/length: must be > 0 (got 0)"},
      {two_bodies(R"({"type": "spring", "a": "world", "b": "a"})"),
       R"(scene.json: /constraints/0/type: unknown constraint type "spring" (valid: distance))"},
      {two_bodies(R"({"a": "world", "b": "world"})"),
       "scene.json: /constraints/0: both ends are fixed"},
      {two_bodies(R"({"a": "world", "b": "s"})"),
       "scene.json: /constraints/0: both ends are fixed"},
      {two_bodies(R"({"a": "a", "b": 0})"),
       "scene.json: /constraints/0: both ends are on the same"},
      {two_bodies(R"({"a": "ghost", "b": "a"})"),
       R"(scene.json: /constraints/0/a: no body named "ghost")"},
      {two_bodies(R"({"a": "world", "b": 5})"),
       "scene.json: /constraints/0/b: body index out of range (got 5)"},
      {two_bodies(R"({"a": "world", "b": true})"),
       "scene.json: /constraints/0/b: expected a body name, a body index or \"world\""},
      {two_bodies(R"({"a": "world"})"), "scene.json: /constraints/0/b: missing (required)"},
      {two_bodies(R"({"a": "world", "b": "a", "anchor_a": [1, 0, 0]})"),
       "scene.json: /constraints/0: the anchor points coincide"},
      // Malformed JSON: the position comes from the parser's byte offset.
      {"{\n  \"name\": \"x\",\n  \"bodies\": [],\n  \"a\":}\n", "scene.json: line 4, column 7: "},
  }));
  CAPTURE(bad.text);
  REQUIRE_THROWS_AS(parse_scene(bad.text, "scene.json"), InputError);
  REQUIRE_THROWS_WITH(parse_scene(bad.text, "scene.json"), Catch::Contains(bad.message));
}

TEST_CASE("a scene file takes every method's own parameters, as --solver NAME:key=value does",
          "[scene_json]") {
  // The same settings by both roads: the scene file's /solver/parameters and the grammar.
  const Scene scene = parse_scene(
      R"({"solver": {"method": "admm", "parameters": {"rho": 0.5, "alpha": 1.2, "adapt": false,
                                                      "rho_min": 1e-6}},
          "bodies": []})",
      "scene.json");
  SolverSettings grammar;
  apply_solver_spec(parse_solver_spec("admm:rho=0.5:alpha=1.2:adapt=off:rho_min=1e-6", "test"),
                    grammar);
  CHECK(scene.solver.method == Method::Admm);
  CHECK(scene.solver.methods.admm.rho == 0.5);
  CHECK(scene.solver.methods.admm.alpha == 1.2);
  CHECK_FALSE(scene.solver.methods.admm.adapt_rho);
  CHECK(scene.solver.methods.admm.rho_min == 1e-6);
  CHECK(method_parameters(Method::Admm, scene.solver.methods) ==
        method_parameters(Method::Admm, grammar.methods));
  // Written and read back: the same parameters, and the file says them.
  const std::string text = scene_to_json(scene);
  CHECK(text.find("\"parameters\"") != std::string::npos);
  CHECK(method_parameters(Method::Admm, parse_scene(text, "back").solver.methods) ==
        method_parameters(Method::Admm, scene.solver.methods));
  // A method without parameters of its own writes none.
  Scene pgs = scene;
  pgs.solver.method = Method::Pgs;
  CHECK(scene_to_json(pgs).find("\"parameters\"") == std::string::npos);
}

TEST_CASE("the solver's row order and seed are read and written, relaxation ranges per method",
          "[scene_json]") {
  const Scene scene =
      parse_scene(R"({"solver": {"method": "pgs", "order": "random", "seed": 42}, "bodies": []})",
                  "scene.json");
  CHECK(scene.solver.order == RowOrder::Random);
  CHECK(scene.solver.seed == 42u);
  const Scene back = parse_scene(scene_to_json(scene), "scene.json");
  CHECK(back.solver.order == RowOrder::Random);
  CHECK(back.solver.seed == 42u);
  // Defaults: the natural order, seed 0 (7.1.1).
  const Scene plain = parse_scene(R"({"bodies": []})", "scene.json");
  CHECK(plain.solver.order == RowOrder::Natural);
  CHECK(plain.solver.seed == 0u);

  const auto error_of = [](const std::string& text) {
    try {
      parse_scene(text, "scene.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(
      error_of(R"({"solver": {"order": "sideways"}, "bodies": []})") ==
      R"(scene.json: /solver/order: unknown row order "sideways" (valid: natural, reverse, random))");
  CHECK(error_of(R"({"solver": {"seed": -1}, "bodies": []})") ==
        "scene.json: /solver/seed: must be >= 0 (got -1)");
  // The --solver grammar's ranges: Jacobi's damping in (0, 1], SOR's omega in (0, 2).
  CHECK(error_of(R"({"solver": {"method": "jacobi", "relaxation": 1.5}, "bodies": []})") ==
        "scene.json: /solver/relaxation: must be in (0, 1] (got 1.5)");
  CHECK(error_of(R"({"solver": {"method": "pgs", "relaxation": 1.5}, "bodies": []})") ==
        "no error");
}

TEST_CASE("/solver/warm_start stays accepted as the factor 1 or 0, warm_friction defaults to warm",
          "[scene_json][warm]") {
  const auto solver_of = [](const std::string& solver) {
    return parse_scene(R"({"solver": )" + solver + R"(, "bodies": []})", "scene.json").solver;
  };
  const SolverSettings plain = solver_of("{}");
  CHECK(plain.warm == 1.0);  // the paper's warm start (7)
  CHECK_FALSE(plain.warm_friction.has_value());
  CHECK_FALSE(plain.contacts_first);
  CHECK(solver_of(R"({"warm_start": true})").warm == 1.0);
  CHECK(solver_of(R"({"warm_start": false})").warm == 0.0);
  CHECK(solver_of(R"({"warm_start": false})").warm_factor(RowKind::Friction) == 0.0);
  const SolverSettings bullet = solver_of(R"({"warm": 0.85, "warm_friction": 0})");
  CHECK(bullet.warm_factor(RowKind::Contact) == 0.85);
  CHECK(bullet.warm_factor(RowKind::Distance) == 0.85);
  CHECK(bullet.warm_factor(RowKind::Friction) == 0.0);
  CHECK(solver_of(R"({"warm": 0.5})").warm_factor(RowKind::Friction) == 0.5);
  CHECK(solver_of(R"({"warm_start": false, "warm_friction": 1})").warm_factor(RowKind::Friction) ==
        1.0);
}
