// A column of liquid at rest on the floor: hydrostatic pressure p = rho0*g*depth, and, for an
// incompressible liquid, no motion: the centroid stays where it starts, within the 1% density
// tolerance of the incompressibility gate (design notes §4) applied to the column height.
// It only rests if it starts at the rest density: Sibernetic's density has no self term, counts
// the 32 nearest neighbours and clamps pressure increments at >= 0 (physics sheet §3.3, §3.6),
// so an under-dense start carries no pressure and sinks. Both densities are predicted here.
#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "owval/base/errors.hpp"
#include "prediction_parts.hpp"

namespace owval::predict::internal {
namespace {

struct Column {
  double surface_cu = -1e30, bottom_cu = 1e30, centroid_cu = 0;
  std::map<long, double> layers;  // layer y (rounded to 1e-3 cu) -> y
  std::size_t particles = 0;
  double spacing_cu = 0;  // between layers
};

Column Measure(const engine::SiberneticConfig& c, double r0_cu) {
  Column col;
  col.spacing_cu = r0_cu;
  for (const auto& p : c.position) {
    if (KindOf(p[3]) != ParticleKind::kLiquid) continue;
    col.surface_cu = std::max(col.surface_cu, double(p[1]));
    col.bottom_cu = std::min(col.bottom_cu, double(p[1]));
    col.centroid_cu += p[1];
    col.layers[std::lround(p[1] * 1000.0)] = p[1];
    ++col.particles;
  }
  col.centroid_cu /= double(col.particles);
  // Each particle stands for a cell of the layer spacing (r0 for a single layer): the free
  // surface is half a spacing above the top layer and the base half a spacing below the bottom.
  // Float positions reproduce r0 only to ~1e-6 cu: keep the nominal r0 unless the layers are
  // truly spaced otherwise (a column generated at the rest spacing, for example).
  const double layer_spacing =
      col.layers.size() > 1 ? (col.surface_cu - col.bottom_cu) / double(col.layers.size() - 1)
                            : r0_cu;
  if (std::abs(layer_spacing - r0_cu) > 1e-4) col.spacing_cu = layer_spacing;
  col.surface_cu += col.spacing_cu / 2;
  col.bottom_cu -= col.spacing_cu / 2;
  return col;
}

// Sibernetic's density (physics sheet §3.3) from squared distances (cu²) to the other particles:
// the 32 nearest within h, no self term, the sum floored at h⁶.
double SiberneticDensity(std::vector<double> r2_cu2, const engine::PhysicsConstants& k) {
  const double h2 = k.h_cu * k.h_cu, s = k.simulation_scale, h_m = k.h_cu * s;
  std::sort(r2_cu2.begin(), r2_cu2.end());
  double sum = 0;
  for (std::size_t j = 0; j < r2_cu2.size() && j < engine::kNeighbourSlots; ++j)
    if (r2_cu2[j] < h2) sum += std::pow(h2 - r2_cu2[j], 3);
  const double w_poly6 = 315 / (64 * kPi * std::pow(h_m, 9));  // m^-9
  return k.mass_kg * w_poly6 * std::pow(s, 6) * std::max(sum, std::pow(k.h_cu, 6));
}

// Density of liquid particle i as the configuration places it (neighbours of every type).
double DensityAt(const engine::SiberneticConfig& c, std::size_t i,
                 const engine::PhysicsConstants& k) {
  std::vector<double> r2;
  for (std::size_t j = 0; j < c.position.size(); ++j) {
    if (j == i) continue;
    double d2 = 0;
    for (int a = 0; a < 3; ++a) d2 += std::pow(double(c.position[i][a]) - c.position[j][a], 2);
    if (d2 <= k.h_cu * k.h_cu) r2.push_back(d2);
  }
  return SiberneticDensity(r2, k);
}

// Density inside an infinite simple-cubic lattice of spacing d (cu).
double CubicLatticeDensity(double d_cu, const engine::PhysicsConstants& k) {
  const int reach = int(std::ceil(k.h_cu / d_cu));
  std::vector<double> r2;
  for (int x = -reach; x <= reach; ++x)
    for (int y = -reach; y <= reach; ++y)
      for (int z = -reach; z <= reach; ++z)
        if (x || y || z) r2.push_back(double(x * x + y * y + z * z) * d_cu * d_cu);
  return SiberneticDensity(r2, k);
}

// The cubic-lattice spacing whose density is rho0 (density falls as the spacing grows).
double RestLatticeSpacing(const engine::PhysicsConstants& k) {
  double dense = 0.25 * k.h_cu, sparse = k.h_cu;
  for (int i = 0; i < 60; ++i) {
    const double mid = (dense + sparse) / 2;
    (CubicLatticeDensity(mid, k) > k.rest_density ? dense : sparse) = mid;
  }
  return (dense + sparse) / 2;
}

// The densest liquid particle's density: the bulk, away from the surface and walls.
double BulkDensity(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k) {
  double densest = 0;
  for (std::size_t i = 0; i < c.position.size(); ++i)
    if (KindOf(c.position[i][3]) == ParticleKind::kLiquid)
      densest = std::max(densest, DensityAt(c, i, k));
  return densest;
}

}  // namespace

Prediction HydrostaticColumn(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k) {
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
  Prediction p;
  p.predictor = "hydrostatic_column";
  p.inputs = {Input("liquid_particles", double(col.particles), "1",
                    "configuration [position]: rows of type 1.x"),
              Input("layers", double(col.layers.size()), "1", "distinct liquid y values"),
              Input("column_height", height_cu, "cu",
                    "liquid top - bottom + one layer spacing (each particle fills a cell)"),
              Input("mass", k.mass_kg, "kg", DefaultSource("mass")),
              Input("h", k.h_cu, "cu", DefaultSource("h")),
              Input("r0", k.r0_cu, "cu", DefaultSource("r0 = h/2")),
              Input("rest_density", rho0, "kg/m^3", DefaultSource("rho0")),
              Input("gravity_y", k.gravity[1], "m/s^2", DefaultSource("gravity_y")),
              Input("simulation_scale", s, "m/cu", DefaultSource("simulationScale"))};
  PredictedQuantity pressure =
      Quantity("bottom_pressure", bottom_pressure, "Pa", bottom_pressure, "Pa",
               "p = rho0 * g * depth * s at the bottom layer", 0, kInformative);
  pressure.detail_key = "profile";
  pressure.detail = profile;
  const double bulk = BulkDensity(c, k), spacing = RestLatticeSpacing(k);
  p.predictions = {
      Quantity("centroid_equilibrium", col.centroid_cu, "cu", col.centroid_cu * s, "m",
               "incompressible column at rest: the starting centroid; tolerance 1% of the column "
               "height (the incompressibility gate's 1% density error)",
               tolerance, kAbsoluteCu),
      pressure,
      Quantity("initial_bulk_density", bulk, "kg/m^3", bulk, "kg/m^3",
               "max over liquid i of m*Wpoly6*max(sum over the 32 nearest j within h of "
               "(h^2 - r_ij^2)^3, h^6), positions from the configuration",
               0, kInformative),
      Quantity("rest_lattice_spacing", spacing, "cu", spacing * s, "m",
               "cubic lattice spacing d at which that density equals rho0", 0, kInformative)};
  if (bulk < 0.99 * rho0)
    p.notes.push_back("the liquid starts under-dense (" + std::to_string(bulk) +
                      " kg/m^3 < rho0): pressure increments are clamped at >= 0, so the column "
                      "sinks until it compacts; a lattice at spacing " +
                      std::to_string(spacing) + " cu starts at rest density");
  p.track = Track{0, "liquid", Axis::kY};
  return p;
}

}  // namespace owval::predict::internal
