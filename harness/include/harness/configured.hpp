#pragma once
// harness::configured — an index in one of its configurations: the base every benchmarked
// interface (point_index, ray_index, collide_index) shares, so that a tuning sweep's member
// (harness/tuning_sweep.hpp, whose add_peer_configurations makes them) carries what it
// changes into its rows. Kept free of the registries: every adapter includes it.

#include <string>
#include <utility>

namespace harness {

class configured {
public:
    // The configuration this instance runs when it is not its registry line's default: a
    // tuning sweep's member ("bucket_size=32;points_cache=on"), which the rows append to their
    // params. "" for the default.
    const std::string& configuration() const { return configuration_; }
    void set_configuration(std::string c) { configuration_ = std::move(c); }

protected:
    ~configured() = default;  // not deleted through this base

private:
    std::string configuration_;
};

// A structure as messages and map keys name it: "embree" for a default configuration,
// "embree[build_quality=high]" for a swept one.
template <class Index>
std::string labelled(const Index& s) {
    return s.configuration().empty() ? s.name() : s.name() + "[" + s.configuration() + "]";
}

}  // namespace harness
