// The nearest points of two segments: where an edge of one surface comes closest to an edge of
// another (edge-against-edge contact, contact_set.hpp).
#pragma once

#include "corotate/common.hpp"

namespace corotate {

struct SegmentPoints {
  double s = 0, t = 0;  // p(s) = a + s (b - a), q(t) = c + t (d - c), both in [0, 1]
  double distance2 = 0;  // |p(s) - q(t)|^2
};

// The parameters of the closest points of segments [a, b] and [c, d] (Ericson, Real-Time
// Collision Detection, 5.1.9): the lines' closest points, each clamped to its segment and the
// other recomputed. Parallel segments give one of the pairs at the nearest distance.
SegmentPoints closest_points_on_segments(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace corotate
