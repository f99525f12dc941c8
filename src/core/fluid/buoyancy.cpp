#include "fluid/buoyancy.h"

namespace flapsim {

Wrench buoyancyLaw(const FluidInput& in, std::vector<Vec3>*) {
  const AeroSurface& surface = in.surface;
  const BodyKinematics& body = in.body;
  const Vec3 force = buoyancyForce(surface.volume, in.air.density, in.gravity);
  const Vec3 centroid =
      body.has_body_frame ? body.rotation * surface.centroid : body.orientation * surface.centroid;
  return Wrench{force, centroid.cross(force)};
}

}  // namespace flapsim
