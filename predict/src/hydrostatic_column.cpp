// A column of liquid at rest on the floor: hydrostatic pressure p = rho0*g*depth, and, for an
// incompressible liquid, no motion: the centroid stays where it starts, within the 1% density
// tolerance of the incompressibility gate (design notes §4) applied to the column height.
#include <algorithm>
#include <cmath>
#include <map>

#include "owval/base/errors.hpp"
#include "prediction_parts.hpp"

namespace owval::predict::internal {
namespace {

struct Column {
  double surface_cu = -1e30, bottom_cu = 1e30, centroid_cu = 0;
  std::map<long, double> layers;  // layer y (rounded to 1e-3 cu) -> y
  std::size_t particles = 0;
};

Column Measure(const engine::SiberneticConfig& c, double r0_cu) {
  Column col;
  for (const auto& p : c.position) {
    if (KindOf(p[3]) != ParticleKind::kLiquid) continue;
    col.surface_cu = std::max(col.surface_cu, double(p[1]));
    col.bottom_cu = std::min(col.bottom_cu, double(p[1]));
    col.centroid_cu += p[1];
    col.layers[std::lround(p[1] * 1000.0)] = p[1];
    ++col.particles;
  }
  col.centroid_cu /= double(col.particles);
  // Each particle stands for a cell of side r0: the free surface is half a spacing above the top
  // layer and the column's base half a spacing below the bottom layer.
  col.surface_cu += r0_cu / 2;
  col.bottom_cu -= r0_cu / 2;
  return col;
}

}  // namespace

nlohmann::json HydrostaticColumn(const engine::SiberneticConfig& c,
                                 const engine::PhysicsConstants& k) {
  const Column col = Measure(c, k.r0_cu);
  if (col.particles < 2)
    throw InputError(c.source, 0, "hydrostatic_column: needs liquid particles");
  const double s = k.simulation_scale, g = -k.gravity[1], rho0 = k.rest_density;
  const double height_cu = col.surface_cu - col.bottom_cu;
  nlohmann::json profile = nlohmann::json::array();
  for (const auto& [key, y] : col.layers)
    profile.push_back({{"layer_y_cu", y},
                       {"depth_cu", col.surface_cu - y},
                       {"pressure_pa", rho0 * g * (col.surface_cu - y) * s}});
  const double bottom_depth = col.surface_cu - col.layers.begin()->second;
  const double bottom_pressure = rho0 * g * bottom_depth * s;
  const double tolerance = 0.01 * height_cu;
  nlohmann::json p;
  p["predictor"] = "hydrostatic_column";
  p["inputs"] = {Input("liquid_particles", double(col.particles), "1",
                       "configuration [position]: rows of type 1.x"),
                 Input("layers", double(col.layers.size()), "1", "distinct liquid y values"),
                 Input("column_height", height_cu, "cu",
                       "liquid top - bottom + r0 (each particle fills a cell of side r0)"),
                 Input("r0", k.r0_cu, "cu", DefaultSource("r0 = h/2")),
                 Input("rest_density", rho0, "kg/m^3", DefaultSource("rho0")),
                 Input("gravity_y", k.gravity[1], "m/s^2", DefaultSource("gravity_y")),
                 Input("simulation_scale", s, "m/cu", DefaultSource("simulationScale"))};
  nlohmann::json pressure =
      Quantity("bottom_pressure", bottom_pressure, "Pa", bottom_pressure, "Pa",
               "p = rho0 * g * depth * s at the bottom layer", 0, kInformative);
  pressure["profile"] = profile;
  p["predictions"] = {
      Quantity("centroid_equilibrium", col.centroid_cu, "cu", col.centroid_cu * s, "m",
               "incompressible column at rest: the starting centroid; tolerance 1% of the column "
               "height (the incompressibility gate's 1% density error)",
               tolerance, kAbsoluteCu),
      pressure};
  p["track"] = {{"group", "liquid"}, {"axis", "y"}};
  return p;
}

}  // namespace owval::predict::internal
