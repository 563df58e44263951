#include "corotate/contact/closest_points_on_segments.hpp"

#include <algorithm>

namespace corotate {

SegmentPoints closest_points_on_segments(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 u = b - a, w = d - c, r = a - c;
  const double uu = u.squaredNorm(), ww = w.squaredNorm(), wr = w.dot(r);
  SegmentPoints out;
  const double tiny = 1e-300;
  if (uu <= tiny && ww <= tiny) {  // two points
    out.distance2 = r.squaredNorm();
    return out;
  }
  if (uu <= tiny) {  // a point against a segment
    out.t = std::clamp(wr / ww, 0.0, 1.0);
  } else {
    const double ur = u.dot(r);
    if (ww <= tiny) {  // a segment against a point
      out.s = std::clamp(-ur / uu, 0.0, 1.0);
    } else {
      const double uw = u.dot(w), denominator = uu * ww - uw * uw;  // >= 0
      // The lines' closest point on the first segment, clamped (any s for parallel lines).
      out.s = denominator > 1e-14 * uu * ww ? std::clamp((uw * wr - ur * ww) / denominator, 0.0, 1.0) : 0.0;
      // The second segment's point nearest p(s); where it clamps, the first recomputed.
      out.t = (uw * out.s + wr) / ww;
      if (out.t < 0) {
        out.t = 0;
        out.s = std::clamp(-ur / uu, 0.0, 1.0);
      } else if (out.t > 1) {
        out.t = 1;
        out.s = std::clamp((uw - ur) / uu, 0.0, 1.0);
      }
    }
  }
  out.distance2 = (a + out.s * u - c - out.t * w).squaredNorm();
  return out;
}

}  // namespace corotate
