#pragma once
// harness::embree_build_quality — the `build_quality` setting of the Embree adapters' registry
// lines (harness/peer_registry.hpp) and tuning sweeps (harness/tuning_sweep.hpp) read as
// Embree 3's RTCBuildQuality. Embree's documentation (rtcSetSceneBuildQuality):
//   low     a two-level BVH built fast, for dynamic scenes; the only mode that uses the
//           per-geometry build quality (rtcSetGeometryBuildQuality), REFIT included;
//   medium  the default: a single-level BVH by SAH binning (Wald, "On fast Construction of
//           SAH-based Bounding Volume Hierarchies", IRT 2007);
//   high    a higher-quality BVH, with spatial splits on triangle meshes (Stich, Friedrich and
//           Dietrich, "Spatial Splits in Bounding Volume Hierarchies", HPG 2009).
// Any other value is std::invalid_argument naming the adapter and the setting.

#include <embree3/rtcore.h>

#include <stdexcept>
#include <string>

#include "harness/tuning_sweep.hpp"

namespace harness {

inline RTCBuildQuality embree_build_quality(const key_values& settings, const std::string& structure) {
    const std::string& v = setting(settings, "build_quality", structure);
    if (v == "low") return RTC_BUILD_QUALITY_LOW;
    if (v == "medium") return RTC_BUILD_QUALITY_MEDIUM;
    if (v == "high") return RTC_BUILD_QUALITY_HIGH;
    throw std::invalid_argument(structure + ": setting build_quality=" + v + " is not low, medium or high");
}

}  // namespace harness
