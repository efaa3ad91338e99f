#pragma once
// Internal: the pieces every predictor assembles (inputs with their source, quantities with
// formula, units and tolerance) and the predictors themselves.
#include <cstddef>
#include <string>

#include "owval/engine/config.hpp"
#include "owval/predict/predict.hpp"

namespace owval::predict::internal {

constexpr double kPi = 3.14159265358979323846;

inline constexpr ToleranceKind kRelative = ToleranceKind::kRelative;
inline constexpr ToleranceKind kAbsoluteCu = ToleranceKind::kAbsoluteCu;
inline constexpr ToleranceKind kInformative = ToleranceKind::kInformative;

PredictionInput Input(const std::string& name, double value, const std::string& unit,
                      const std::string& source);
PredictedQuantity Quantity(const std::string& name, double value, const std::string& unit,
                           double value_in_si, const std::string& si_unit,
                           const std::string& formula, double tolerance,
                           ToleranceKind tolerance_kind);

enum class Section { kPosition, kVelocity, kConnection };
// "configuration line L ([position] row i)" for a file laid out one value per line, as
// Sibernetic's files and WriteSiberneticConfig are.
std::string ConfigSource(const engine::SiberneticConfig& config, Section section, std::size_t row);
std::string DefaultSource(const std::string& what);

// Sibernetic's worm-body range: springs get full stiffness only when both ends are inside it.
bool WormBody(float type);
// The factor sphFluid.cl applies to a spring between particles of these types.
double SpringFactor(float type_a, float type_b, const engine::PhysicsConstants& k,
                    const PredictOptions& o);
// Period of a harmonic mode of angular frequency omega (rad/s) under semi-implicit Euler.
double SymplecticEulerPeriod(double omega, double dt_s);

Prediction HarmonicSpring(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k,
                          const PredictOptions& o);
Prediction FreeFall(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k);
Prediction HangingChain(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k,
                        const PredictOptions& o);
Prediction HydrostaticColumn(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k);
// The WCSPH scenarios (wcsph_tanks.cpp).
Prediction HydrostaticTank(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k);
Prediction DamBreak(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k);

}  // namespace owval::predict::internal
