#pragma once
// Eigen's dense module, included through this header by every file that uses it, so that a
// build for an AVX-512 machine (-march=native) prints no warnings under GCC 12.
//
// GCC 12's own AVX-512 intrinsics build their "undefined" vectors by self-initialisation
// (`__m512d __Y = __Y;`), and its -Wuninitialized / -Wmaybe-uninitialized report them once
// inlined into Eigen's AVX-512 packet code (ptranspose): a false warning per inlined call
// (GCC bug 105593; opencv, highway and opendcdiag met it too). At -O3 its -Warray-bounds
// also reports the 8-lane loads of Eigen's packet paths on a 3 x 3 matrix (LLT in the
// ellipsoid fit), in branches Eigen guards by the size. They are silenced for this
// include only: warnings located in our own code stay on.

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Warray-bounds"
#include <Eigen/Dense>
#pragma GCC diagnostic pop
#else
#include <Eigen/Dense>
#endif
