#pragma once
// datasets::scene_motion<Object> — moves the objects of one scene set between steps, as its
// motion_description says (scene.hpp):
//
//   static          nothing: moves() is false and step() returns at once, so a runner can skip
//                   every index update for the set.
//   linear          each object (a mesh set: the whole mesh) keeps a velocity of magnitude
//                   `speed`, along `direction` or a uniformly random one; it bounces off the
//                   domain walls.
//   random_walk     each step moves each object (a mesh set: the whole mesh) by a Gaussian
//                   displacement N(0, (speed * dt)^2) per axis; it bounces off the walls too.
//   rigid_rotation  the whole set turns by angular_speed * dt per step about `centre` (3D: about
//                   `axis`). Triangle vertices and points rotate; boxes and spheres move their
//                   centres (a box stays axis-aligned: boxes are not orientable objects). No
//                   walls: the author places the set so that it stays where it should.
//
// Bounce: after a move, on each axis where a body's bounding box is past a wall while it moves
// further out, its velocity component flips (linear) and it is mirrored back inside: moved in by
// twice its overshoot, or less if the opposite wall is closer. A body that fits in the domain is
// therefore entirely inside after every step; one larger than the domain only flips direction.
//
// Arithmetic is in double; each coordinate is rounded to T once per step. Rotations use the
// deterministic sin/cos of deterministic_math.hpp, so motion is reproducible across machines.
// The per-object state (velocities) follows the runner's object order: when churn inserts
// objects at the end, call insert(); when it erases index i by swap-and-pop, call erase(i).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "datasets/deterministic_math.hpp"
#include "datasets/random.hpp"
#include "datasets/scene.hpp"
#include "datasets/scene_objects.hpp"
#include "datasets/scene_streams.hpp"

namespace datasets {

namespace detail {

template <std::size_t D>
using dvec = std::array<double, D>;

template <class T, std::size_t D>
void translate(spatial::point<T, D>& p, const dvec<D>& delta) {
    for (std::size_t d = 0; d < D; ++d) p[d] = static_cast<T>(static_cast<double>(p[d]) + delta[d]);
}
template <class T, std::size_t D>
void translate(spatial::objects::box<T, D>& b, const dvec<D>& delta) {
    for (std::size_t d = 0; d < D; ++d) {
        b.lo[d] = static_cast<T>(static_cast<double>(b.lo[d]) + delta[d]);
        b.hi[d] = static_cast<T>(static_cast<double>(b.hi[d]) + delta[d]);
    }
}
template <class T, std::size_t D>
void translate(spatial::objects::sphere<T, D>& s, const dvec<D>& delta) {
    auto c = s.center();
    translate(c, delta);
    s = spatial::objects::sphere<T, D>(c, s.radius());
}
template <class T, std::size_t D>
void translate(spatial::objects::triangle<T, D>& t, const dvec<D>& delta) {
    std::array<spatial::point<T, D>, 3> v{t.vertex(0), t.vertex(1), t.vertex(2)};
    for (auto& p : v) translate(p, delta);
    t = spatial::objects::triangle<T, D>(v[0], v[1], v[2]);
}

// A rotation x -> centre + R (x - centre), R row-major.
template <std::size_t D>
struct rotation_about {
    std::array<dvec<D>, D> r{};
    dvec<D> centre{};

    template <class T>
    spatial::point<T, D> operator()(const spatial::point<T, D>& p) const {
        dvec<D> x{};
        for (std::size_t d = 0; d < D; ++d) x[d] = static_cast<double>(p[d]) - centre[d];
        spatial::point<T, D> q;
        for (std::size_t i = 0; i < D; ++i) {
            double s = centre[i];
            for (std::size_t j = 0; j < D; ++j) s = std::fma(r[i][j], x[j], s);
            q[i] = static_cast<T>(s);
        }
        return q;
    }
};

// Rotation by `angle` radians: 2D counter-clockwise; 3D about `axis` (non-zero; Rodrigues).
template <std::size_t D>
rotation_about<D> make_rotation(double angle, const scene_vector& axis, const scene_vector& centre) {
    constexpr double two_pi = 6.283185307179586476925286766559;
    double turns = angle / two_pi;
    turns -= std::floor(turns);  // [0, 1], as deterministic_sin_cos_turns wants [0, 1)
    if (turns >= 1) turns = 0;
    const sin_cos sc = deterministic_sin_cos_turns(turns);
    const double c = sc.cos, s = sc.sin, k = 1 - c;
    rotation_about<D> rot;
    for (std::size_t d = 0; d < D; ++d) rot.centre[d] = centre[d];
    if constexpr (D == 2) {
        rot.r = {{{c, -s}, {s, c}}};
    } else {
        const double length = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        const double x = axis[0] / length, y = axis[1] / length, z = axis[2] / length;
        rot.r = {{{c + x * x * k, x * y * k - z * s, x * z * k + y * s},
                  {y * x * k + z * s, c + y * y * k, y * z * k - x * s},
                  {z * x * k - y * s, z * y * k + x * s, c + z * z * k}}};
    }
    return rot;
}

template <class T, std::size_t D>
void rotate(spatial::point<T, D>& p, const rotation_about<D>& rot) {
    p = rot(p);
}
template <class T, std::size_t D>
void rotate(spatial::objects::box<T, D>& b, const rotation_about<D>& rot) {
    const auto c = b.center();
    const auto moved = rot(c);
    dvec<D> delta{};
    for (std::size_t d = 0; d < D; ++d) delta[d] = static_cast<double>(moved[d]) - static_cast<double>(c[d]);
    translate(b, delta);
}
template <class T, std::size_t D>
void rotate(spatial::objects::sphere<T, D>& s, const rotation_about<D>& rot) {
    s = spatial::objects::sphere<T, D>(rot(s.center()), s.radius());
}
template <class T, std::size_t D>
void rotate(spatial::objects::triangle<T, D>& t, const rotation_about<D>& rot) {
    t = spatial::objects::triangle<T, D>(rot(t.vertex(0)), rot(t.vertex(1)), rot(t.vertex(2)));
}

template <std::size_t D>
struct bounds {
    dvec<D> lo, hi;
};

template <class T, std::size_t D>
bounds<D> bounds_of_object(const spatial::point<T, D>& p) {
    bounds<D> b;
    for (std::size_t d = 0; d < D; ++d) b.lo[d] = b.hi[d] = static_cast<double>(p[d]);
    return b;
}
template <class Object>
bounds<Object::dimension> bounds_of_object(const Object& o) {
    bounds<Object::dimension> b;
    for (std::size_t d = 0; d < Object::dimension; ++d) {
        b.lo[d] = static_cast<double>(o.get_min_bound()[d]);
        b.hi[d] = static_cast<double>(o.get_max_bound()[d]);
    }
    return b;
}

// The bounce of a body with bounds `b` that just moved by `moved` (sign per axis): the shift
// that mirrors it back inside, and which axes flip (see the header comment).
template <std::size_t D>
dvec<D> bounce(const bounds<D>& b, const dvec<D>& moved, const scene_vector& lo, const scene_vector& hi,
               std::array<bool, D>& flip) {
    dvec<D> shift{};
    for (std::size_t d = 0; d < D; ++d) {
        flip[d] = false;
        const bool fits = b.hi[d] - b.lo[d] <= hi[d] - lo[d];
        if (b.lo[d] < lo[d] && moved[d] < 0) {
            flip[d] = true;
            if (fits) shift[d] = std::min(2 * (lo[d] - b.lo[d]), hi[d] - b.hi[d]);
        } else if (b.hi[d] > hi[d] && moved[d] > 0) {
            flip[d] = true;
            if (fits) shift[d] = -std::min(2 * (b.hi[d] - hi[d]), b.lo[d] - lo[d]);
        }
    }
    return shift;
}

// Whether a body with bounds `b` reaches past a wall on some axis: only then can bounce()
// shift or flip anything. Without a branch per axis, so that the common case (every wall
// far) costs a few comparisons.
template <std::size_t D>
bool past_a_wall(const bounds<D>& b, const scene_vector& lo, const scene_vector& hi) {
    bool past = false;
    for (std::size_t d = 0; d < D; ++d) {
        past |= b.lo[d] < lo[d];
        past |= b.hi[d] > hi[d];
    }
    return past;
}

template <std::size_t D>
bool nonzero(const dvec<D>& v) {
    for (double x : v)
        if (x != 0) return true;
    return false;
}

}  // namespace detail

template <scene_object Object>
class scene_motion {
public:
    using object_type = Object;
    using scalar_type = typename Object::scalar_type;
    static constexpr std::size_t dimension = Object::dimension;

    // The motion of set `set_index` for `object_count` objects (its initial objects; state for
    // churned objects follows through insert/erase). Linear velocities are drawn here, in
    // object order, from the set's motion stream. Throws std::invalid_argument when Object does
    // not match the set's kind or the scene's dimension.
    scene_motion(const scene_description& scene, std::size_t set_index, std::size_t object_count)
        : motion_(detail::checked_set<Object>(scene, set_index, "scene_motion").motion),
          domain_lo_(scene.domain_lo),
          domain_hi_(scene.domain_hi),
          rigid_body_(scene.objects[set_index].is_mesh()),
          rng_(scene_stream_seed(scene.seed, set_index, scene_stream::motion)),
          count_(object_count) {
        if (motion_.kind == motion_kind::linear) {
            const std::size_t bodies = rigid_body_ ? 1 : object_count;
            velocity_.reserve(bodies);
            for (std::size_t i = 0; i < bodies; ++i) velocity_.push_back(draw_velocity());
        }
    }

    // False for static motion: step() does nothing, and the set's indexes never need updates.
    bool moves() const noexcept { return motion_.kind != motion_kind::static_; }
    // True for a mesh set: all its objects move together (one velocity, one bounce).
    bool rigid_body() const noexcept { return rigid_body_; }
    const motion_description& description() const noexcept { return motion_; }
    // How many objects the state is for (objects.size() that step() expects).
    std::size_t size() const noexcept { return count_; }
    // Linear motion of a generator set: object i's velocity (domain units per second).
    const std::array<double, dimension>& velocity(std::size_t i) const { return velocity_.at(i); }

    // Moves every object by one step of dt seconds. objects.size() must equal size().
    // O(n). Throws std::invalid_argument on a size mismatch.
    void step(std::span<Object> objects, double dt) {
        if (!moves()) return;
        if (objects.size() != count_)
            throw std::invalid_argument("scene_motion::step: " + std::to_string(objects.size()) +
                                        " objects for a motion state of " + std::to_string(count_));
        switch (motion_.kind) {
            case motion_kind::static_: return;
            case motion_kind::linear: return rigid_body_ ? linear_body(objects, dt) : linear_each(objects, dt);
            case motion_kind::random_walk: return rigid_body_ ? walk_body(objects, dt) : walk_each(objects, dt);
            case motion_kind::rigid_rotation: return rotate_all(objects, dt);
        }
    }

    // Churn: `count` objects were appended at the end of the runner's sequence (velocities
    // drawn now, in order). Throws std::logic_error for a mesh set (churn never targets one).
    void insert(std::size_t count = 1) {
        if (rigid_body_) throw std::logic_error("scene_motion::insert: a mesh set moves as one body");
        if (motion_.kind == motion_kind::linear)
            for (std::size_t i = 0; i < count; ++i) velocity_.push_back(draw_velocity());
        count_ += count;
    }
    // Churn: the object at `index` was erased by moving the last object into its place.
    void erase(std::size_t index) {
        if (rigid_body_) throw std::logic_error("scene_motion::erase: a mesh set moves as one body");
        if (index >= count_) throw std::out_of_range("scene_motion::erase: index out of range");
        if (motion_.kind == motion_kind::linear) {
            velocity_[index] = velocity_.back();
            velocity_.pop_back();
        }
        --count_;
    }

private:
    using dvec = detail::dvec<dimension>;

    dvec draw_velocity() {
        dvec v{};
        if (motion_.direction) {
            double sum = 0;
            for (std::size_t d = 0; d < dimension; ++d) {
                v[d] = (*motion_.direction)[d];
                sum = std::fma(v[d], v[d], sum);
            }
            const double length = std::sqrt(sum);
            for (auto& x : v) x /= length;
        } else {
            double length = 0;  // a uniformly random direction: a normalised Gaussian vector
            v = nonzero_gaussian_vector<dimension>(rng_, length);
            for (auto& x : v) x /= length;
        }
        for (auto& x : v) x *= motion_.speed;
        return v;
    }

    dvec gaussian_step(double dt) {
        dvec delta{};
        for (auto& x : delta) x = motion_.speed * dt * rng_.gaussian();
        return delta;
    }

    // Moves one object by delta and bounces it; flips `velocity` (if given) on bounced axes.
    void move_and_bounce(Object& o, const dvec& delta, dvec* velocity) {
        detail::translate(o, delta);
        const auto b = detail::bounds_of_object(o);
        if (!detail::past_a_wall(b, domain_lo_, domain_hi_)) return;  // no bounce: nearly every body, every step
        std::array<bool, dimension> flip{};
        const dvec shift = detail::bounce(b, delta, domain_lo_, domain_hi_, flip);
        if (velocity)
            for (std::size_t d = 0; d < dimension; ++d)
                if (flip[d]) (*velocity)[d] = -(*velocity)[d];
        if (detail::nonzero(shift)) detail::translate(o, shift);
    }

    void linear_each(std::span<Object> objects, double dt) {
        for (std::size_t i = 0; i < objects.size(); ++i) {
            dvec delta{};
            for (std::size_t d = 0; d < dimension; ++d) delta[d] = velocity_[i][d] * dt;
            move_and_bounce(objects[i], delta, &velocity_[i]);
        }
    }

    void walk_each(std::span<Object> objects, double dt) {
        for (auto& o : objects) move_and_bounce(o, gaussian_step(dt), nullptr);
    }

    // A mesh: every triangle moves by the same delta, then the mesh's box bounces as one.
    void move_body(std::span<Object> objects, const dvec& delta, dvec* velocity) {
        detail::bounds<dimension> box;
        box.lo.fill(std::numeric_limits<double>::infinity());
        box.hi.fill(-std::numeric_limits<double>::infinity());
        for (auto& o : objects) {
            detail::translate(o, delta);
            const auto b = detail::bounds_of_object(o);
            for (std::size_t d = 0; d < dimension; ++d) {
                box.lo[d] = std::min(box.lo[d], b.lo[d]);
                box.hi[d] = std::max(box.hi[d], b.hi[d]);
            }
        }
        std::array<bool, dimension> flip{};
        const dvec shift = detail::bounce(box, delta, domain_lo_, domain_hi_, flip);
        if (velocity)
            for (std::size_t d = 0; d < dimension; ++d)
                if (flip[d]) (*velocity)[d] = -(*velocity)[d];
        if (detail::nonzero(shift))
            for (auto& o : objects) detail::translate(o, shift);
    }

    void linear_body(std::span<Object> objects, double dt) {
        dvec delta{};
        for (std::size_t d = 0; d < dimension; ++d) delta[d] = velocity_[0][d] * dt;
        move_body(objects, delta, &velocity_[0]);
    }

    void walk_body(std::span<Object> objects, double dt) { move_body(objects, gaussian_step(dt), nullptr); }

    void rotate_all(std::span<Object> objects, double dt) {
        if (!(dt == rotation_dt_)) {  // one rotation per distinct dt (the scene's time_step)
            rotation_ = detail::make_rotation<dimension>(motion_.angular_speed * dt, motion_.axis, motion_.centre);
            rotation_dt_ = dt;
        }
        for (auto& o : objects) detail::rotate(o, rotation_);
    }

    motion_description motion_;
    scene_vector domain_lo_, domain_hi_;
    bool rigid_body_ = false;
    random_stream rng_;
    std::size_t count_ = 0;
    std::vector<dvec> velocity_;  // linear: one per object, or one for a mesh body
    detail::rotation_about<dimension> rotation_{};
    double rotation_dt_ = std::nan("");
};

}  // namespace datasets
