#include "wcsph/wcsph.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "neighbours/near_candidates.hpp"
#include "owval/base/errors.hpp"
#include "owval/engine/muscles.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {
namespace {

// The median over up to 512 sampled liquid particles of the distance to the nearest other
// liquid particle (brute force: O(512 N), done once).
double MedianNearestDistance(const std::vector<std::array<double, 3>>& liquid) {
  const std::size_t n = liquid.size(), stride = std::max<std::size_t>(1, n / 512);
  std::vector<double> nearest;
  for (std::size_t i = 0; i < n; i += stride) {
    double best = INFINITY;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const double dx = liquid[i][0] - liquid[j][0], dy = liquid[i][1] - liquid[j][1],
                   dz = liquid[i][2] - liquid[j][2];
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (d2 > 0) best = std::min(best, d2);
    }
    if (std::isfinite(best)) nearest.push_back(std::sqrt(best));
  }
  if (nearest.empty()) return 0;
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  return nearest[nearest.size() / 2];
}

template <typename T>
void Permute(const std::vector<std::int32_t>& order, std::vector<T>* v) {
  std::vector<T> out(v->size());
  for (std::size_t k = 0; k < order.size(); ++k) out[k] = (*v)[order[k]];
  v->swap(out);
}

}  // namespace

Wcsph::Wcsph(const SiberneticConfig& config, const PhysicsConstants& constants, int threads)
    : p_(constants.wcsph), threads_(std::max(1, threads)), muscles_(kMuscleCount, 0.0f) {
  if (config.elastic_count() > 0)
    throw InputError(config.source, 0,
                     "backend wcsph simulates liquid and boundary particles only: the "
                     "configuration has " +
                         std::to_string(config.elastic_count()) + " elastic particles");
  if (config.liquid_count() == 0)
    throw InputError(config.source, 0, "backend wcsph needs liquid particles: there are none");
  scale_ = constants.simulation_scale;
  nominal_dt_ = constants.time_step_s;
  rho0_ = constants.rest_density;
  for (int a = 0; a < 3; ++a) gravity_[a] = float(constants.gravity[a]);
  const std::size_t n = config.particle_count();
  State& s = s_;
  for (auto* v : {&s.x, &s.y, &s.z, &s.vx, &s.vy, &s.vz, &s.ax, &s.ay, &s.az, &s.rho})
    v->assign(n, 0.0f);
  s.row.resize(n);
  s.liquid.resize(n);
  out_position_.resize(n);
  out_velocity_.resize(n);
  wall_velocity_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Row4 &x = config.position[i], &v = config.velocity[i];
    s.row[i] = std::int32_t(i);
    s.liquid[i] = IsLiquid(x[3]);
    s.x[i] = float(x[0] * scale_);
    s.y[i] = float(x[1] * scale_);
    s.z[i] = float(x[2] * scale_);
    out_position_[i] = {x[0], x[1], x[2], x[3]};
    wall_velocity_[i] = {v[0], v[1], v[2], v[3]};
    if (s.liquid[i]) {
      s.vx[i] = v[0];
      s.vy[i] = v[1];
      s.vz[i] = v[2];
    }
  }
  DeriveScales(config, constants);
  kernel_ = WendlandC2<float>::ForRadius(h_);
  const double margin = 2 * h_;
  for (int a = 0; a < 3; ++a) {
    box_low_[a] = float(config.box.lower(a) * scale_);
    box_high_[a] = float(config.box.upper(a) * scale_);
  }
  const float low[3] = {float(box_low_[0] - margin), float(box_low_[1] - margin),
                        float(box_low_[2] - margin)};
  const float high[3] = {float(box_high_[0] + margin), float(box_high_[1] + margin),
                         float(box_high_[2] + margin)};
  cells_.Configure(low, high, kernel_.support);
  pressure_.assign(n, 0.0f);
  drho_.assign(n, 0.0f);
  xsph_x_.assign(n, 0.0f);
  xsph_y_.assign(n, 0.0f);
  xsph_z_.assign(n, 0.0f);
  out_pressure_.assign(n, 0.0f);
  out_density_.assign(n, 0.0f);
  list_.assign(n, nullptr);
  list_count_.assign(n, 0);
  scratch_.resize(std::size_t(threads_));
  list_begin_.assign(n, 0);
  list_owner_.assign(n, 0);
  if (p_.morton_reorder) Reorder();
  BuildNeighbours();
  Evaluate();
  WriteOutputs();
}

// Spacing, h, mass, the liquid's height, c_s and Tait's B; the initial densities.
void Wcsph::DeriveScales(const SiberneticConfig& config, const PhysicsConstants& constants) {
  std::vector<std::array<double, 3>> liquid;
  for (std::size_t i = 0; i < s_.x.size(); ++i)
    if (s_.liquid[i]) liquid.push_back({double(s_.x[i]), double(s_.y[i]), double(s_.z[i])});
  spacing_m_ = p_.spacing_m > 0 ? p_.spacing_m : MedianNearestDistance(liquid);
  if (!(spacing_m_ > 0)) spacing_m_ = constants.r0_cu * scale_;
  h_ = p_.h_factor * spacing_m_;
  mass_ = rho0_ * spacing_m_ * spacing_m_ * spacing_m_;
  const double g = std::sqrt(double(gravity_[0]) * gravity_[0] + double(gravity_[1]) * gravity_[1] +
                             double(gravity_[2]) * gravity_[2]);
  // Depth along gravity: the liquid's top sits half a spacing above its highest particle.
  double top = INFINITY, bottom = -INFINITY;
  const auto along = [&](const std::array<double, 3>& x) {
    return g > 0 ? (x[0] * gravity_[0] + x[1] * gravity_[1] + x[2] * gravity_[2]) / g : 0.0;
  };
  for (const auto& x : liquid) {
    top = std::min(top, along(x));
    bottom = std::max(bottom, along(x));
  }
  const double height = g > 0 ? bottom - top + spacing_m_ : 0;
  sound_speed_ =
      std::max(p_.sound_speed_factor * std::sqrt(2 * g * height), p_.min_sound_speed_m_s);
  if (!(sound_speed_ > 0))
    throw InputError(config.source, 0,
                     "backend wcsph: the speed of sound is 0 (no gravity or no liquid height): "
                     "set wcsph_min_sound_speed_m_s");
  tait_b_ = sound_speed_ * sound_speed_ * rho0_ / p_.tait_gamma;
  // Walls start at the density of the liquid beside them, or ρ0 above the liquid's surface.
  for (std::size_t i = 0; i < s_.x.size(); ++i) {
    s_.rho[i] = float(rho0_);
    if (!p_.hydrostatic_start || g == 0) continue;
    const double depth =
        along({double(s_.x[i]), double(s_.y[i]), double(s_.z[i])}) - top + 0.5 * spacing_m_;
    if (depth <= 0) continue;
    s_.rho[i] = float(rho0_ * std::pow(1 + rho0_ * g * depth / tait_b_, 1 / p_.tait_gamma));
  }
}

float Wcsph::Pressure(float rho) const {
  const float r = rho / float(rho0_);
  if (p_.tait_gamma == 7) {
    const float r2 = r * r, r4 = r2 * r2;
    return float(tait_b_) * (r4 * r2 * r - 1.0f);
  }
  return float(tait_b_) * (std::pow(r, float(p_.tait_gamma)) - 1.0f);
}

// Sorts the particle arrays by the Morton key of their cell (ties by current index, so the
// order is deterministic).
void Wcsph::Reorder() {
  const std::size_t n = s_.x.size();
  std::vector<std::pair<std::uint32_t, std::int32_t>> keyed(n);
  for (std::size_t i = 0; i < n; ++i)
    keyed[i] = {cells_.MortonKey(cells_.Cell(s_.x[i], s_.y[i], s_.z[i])), std::int32_t(i)};
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::int32_t> order(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = keyed[k].second;
  for (auto* v : {&s_.x, &s_.y, &s_.z, &s_.vx, &s_.vy, &s_.vz, &s_.ax, &s_.ay, &s_.az, &s_.rho})
    Permute(order, v);
  Permute(order, &s_.row);
  Permute(order, &s_.liquid);
}

// Cell list, then each computed particle's list: a liquid particle lists every particle within
// the support, a wall particle (computed only when a liquid particle is within one cell) lists
// the liquid ones. Lists are built cell by cell (ListCell), each cell by one thread; within a
// list, neighbours come in the order of the 27 cells and of the index within a cell.
void Wcsph::BuildNeighbours() {
  const std::size_t n = s_.x.size();
  cells_.Build(s_.x.data(), s_.y.data(), s_.z.data(), n);
  cell_has_liquid_.assign(std::size_t(cells_.cells()), 0);
  cell_active_.assign(std::size_t(cells_.cells()), 0);
  for (std::size_t i = 0; i < n; ++i)
    if (s_.liquid[i]) cell_has_liquid_[std::size_t(cells_.CellOf(i))] = 1;
  int around[27];
  active_cells_.clear();
  for (int c = 0; c < cells_.cells(); ++c) {
    if (!cell_has_liquid_[std::size_t(c)]) continue;
    const int count = cells_.Around(c, around);
    for (int k = 0; k < count; ++k) cell_active_[std::size_t(around[k])] = 1;
  }
  for (int c = 0; c < cells_.cells(); ++c)
    if (cell_active_[std::size_t(c)] && cells_.begin(c) != cells_.end(c))
      active_cells_.push_back(c);
  process_.clear();
  liquid32_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    liquid32_[i] = s_.liquid[i];
    if (s_.liquid[i]) process_.push_back(std::int32_t(i));
  }
  process_liquid_ = process_.size();
  for (std::size_t i = 0; i < n; ++i)
    if (!s_.liquid[i] && cell_active_[std::size_t(cells_.CellOf(i))])
      process_.push_back(std::int32_t(i));
#pragma omp parallel num_threads(threads_)
  {
    const int thread = omp_get_thread_num();
    ListScratch& scratch = scratch_[std::size_t(thread)];
    scratch.lists.clear();
#pragma omp for schedule(dynamic, 8)
    for (std::size_t k = 0; k < active_cells_.size(); ++k)
      ListCell(active_cells_[k], &scratch, thread);
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < process_.size(); ++k) {
      const std::size_t i = std::size_t(process_[k]);
      list_[i] = scratch_[std::size_t(list_owner_[i])].lists.data() + list_begin_[i];
    }
  }
}

void Wcsph::Candidates::Clear() {
  x.clear();
  y.clear();
  z.clear();
  index.clear();
}

void Wcsph::Candidates::Add(const State& s, std::int32_t j) {
  x.push_back(s.x[std::size_t(j)]);
  y.push_back(s.y[std::size_t(j)]);
  z.push_back(s.z[std::size_t(j)]);
  index.push_back(j);
}

// The lists of one cell's particles: the particles of its 27 cells within the support of the
// cell's box (a third of them fall further) gathered once into contiguous candidates, then each
// particle keeps those within its support (NearCandidates: AVX-512 when the CPU has it).
void Wcsph::ListCell(int cell, ListScratch* scratch, int thread) {
  ListScratch& c = *scratch;
  c.all.Clear();
  c.liquid.Clear();
  float low[3], high[3];
  cells_.Bounds(cell, low, high);
  const float support2 = kernel_.support2, slack = 1e-3f * kernel_.support;
  const auto outside = [&](float v, int a) {
    return std::max(0.0f, std::max(low[a] - slack - v, v - high[a] - slack));
  };
  int around[27];
  const int count = cells_.Around(cell, around);
  for (int a = 0; a < count; ++a)
    for (const std::int32_t* j = cells_.begin(around[a]); j != cells_.end(around[a]); ++j) {
      const float dx = outside(s_.x[*j], 0), dy = outside(s_.y[*j], 1), dz = outside(s_.z[*j], 2);
      if (dx * dx + dy * dy + dz * dz >= support2) continue;
      c.all.Add(s_, *j);
      if (s_.liquid[*j]) c.liquid.Add(s_, *j);
    }
  c.kept.resize(c.all.index.size() + kNearSlack);
  c.d2.resize(c.kept.size());
  for (const std::int32_t* p = cells_.begin(cell); p != cells_.end(cell); ++p) {
    const std::size_t i = std::size_t(*p);
    const Candidates& from = s_.liquid[i] ? c.all : c.liquid;
    const CandidateCell candidates{from.index.data(), from.x.data(), from.y.data(), from.z.data(),
                                   int(from.index.size())};
    const float at[3] = {s_.x[i], s_.y[i], s_.z[i]};
    const int kept = NearCandidates(candidates, at, support2, *p, c.kept.data(), c.d2.data());
    list_begin_[i] = c.lists.size();
    list_owner_[i] = thread;
    list_count_[i] = kept;
    c.lists.insert(c.lists.end(), c.kept.begin(), c.kept.begin() + kept);
  }
}

// Pressures of all, accelerations of the liquid, at the current positions and densities.
void Wcsph::Evaluate() {
  const std::size_t n = s_.x.size();
#pragma omp parallel num_threads(threads_)
  {
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) pressure_[i] = Pressure(s_.rho[i]);
#pragma omp for schedule(dynamic, 256)
    for (std::size_t k = 0; k < process_liquid_; ++k) Accelerate(std::size_t(process_[k]));
  }
}

// The density rates of every computed particle and the liquid's XSPH velocities.
void Wcsph::DensityRates() {
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads_)
  for (std::size_t k = 0; k < process_.size(); ++k) DensityRate(std::size_t(process_[k]));
}

// ρ += dt Dρ for every computed particle; walls never fall below ρ0 (they do not pull [CGD07]).
void Wcsph::AdvanceDensity(double dt) {
  const float step = float(dt), floor = float(rho0_);
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t k = 0; k < process_.size(); ++k) {
    const std::size_t i = std::size_t(process_[k]);
    s_.rho[i] += step * drho_[i];
    if (k >= process_liquid_) s_.rho[i] = std::max(s_.rho[i], floor);
  }
}

void Wcsph::Kick(double half_dt) {
  const float half = float(half_dt);
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t k = 0; k < process_liquid_; ++k) {
    const std::size_t i = std::size_t(process_[k]);
    s_.vx[i] += half * s_.ax[i];
    s_.vy[i] += half * s_.ay[i];
    s_.vz[i] += half * s_.az[i];
  }
}

// x += dt u (XSPH velocity), kept inside the box (a leak through a one-layer wall stops there).
void Wcsph::Drift(double dt) {
  const float step = float(dt);
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t k = 0; k < process_liquid_; ++k) {
    const std::size_t i = std::size_t(process_[k]);
    s_.x[i] = std::clamp(s_.x[i] + step * xsph_x_[i], box_low_[0], box_high_[0]);
    s_.y[i] = std::clamp(s_.y[i] + step * xsph_y_[i], box_low_[1], box_high_[1]);
    s_.z[i] = std::clamp(s_.z[i] + step * xsph_z_[i], box_low_[2], box_high_[2]);
  }
}

// Kick-drift-kick; the drift carries the density with the positions (see wcsph.hpp). The rates
// of the first kick are those of the last evaluation.
void Wcsph::Substep(double dt) {
  Kick(0.5 * dt);
  clock_.Mark(kKick);
  DensityRates();
  AdvanceDensity(dt);
  clock_.Mark(kDensity);
  Drift(dt);
  clock_.Mark(kDrift);
  if (p_.morton_reorder && ++s_.since_reorder >= std::size_t(p_.reorder_interval)) {
    Reorder();
    s_.since_reorder = 0;
  }
  clock_.Mark(kReorder);
  BuildNeighbours();
  clock_.Mark(kNeighbours);
  Evaluate();
  clock_.Mark(kForces);
  Kick(0.5 * dt);
  clock_.Mark(kKick);
  s_.time_s += dt;
}

double Wcsph::SafeDt() const {
  float v2 = 0, a2 = 0;
  const std::size_t n = s_.x.size();
#pragma omp parallel for schedule(static) num_threads(threads_) reduction(max : v2, a2)
  for (std::size_t i = 0; i < n; ++i) {
    if (!s_.liquid[i]) continue;
    v2 = std::max(v2, s_.vx[i] * s_.vx[i] + s_.vy[i] * s_.vy[i] + s_.vz[i] * s_.vz[i]);
    a2 = std::max(a2, s_.ax[i] * s_.ax[i] + s_.ay[i] * s_.ay[i] + s_.az[i] * s_.az[i]);
  }
  double dt = h_ / (sound_speed_ + std::sqrt(double(v2)));
  if (a2 > 0) dt = std::min(dt, std::sqrt(h_ / std::sqrt(double(a2))));
  return p_.cfl * dt;
}

double Wcsph::MaxDensityVariation() const {
  float worst = 0;
  const float rho0 = float(rho0_);
  const std::size_t n = s_.x.size();
#pragma omp parallel for schedule(static) num_threads(threads_) reduction(max : worst)
  for (std::size_t i = 0; i < n; ++i)
    if (s_.liquid[i]) worst = std::max(worst, std::abs(s_.rho[i] - rho0));
  return double(worst) / rho0_;
}

void Wcsph::Checkpoint() { checkpoint_ = s_; }

void Wcsph::Restore() {
  s_ = checkpoint_;
  BuildNeighbours();
  WriteOutputs();
}

// A safe sub-step so short that the nominal step would take more than kMaxSubstepsPerStep of
// them (or that no longer advances the clock) means the forces blew up: the run ends as a
// simulation failure instead of never finishing.
void Wcsph::CheckProgress(double safe) const {
  if (std::isnan(safe)) return;  // a NaN state: Run stops on it with a state dump
  if (safe >= nominal_dt_ / kMaxSubstepsPerStep && s_.time_s + safe > s_.time_s) return;
  std::ostringstream msg;
  msg.precision(3);
  msg << "wcsph: the adaptive time step fell to " << safe << " s at step " << step_
      << " (more than " << kMaxSubstepsPerStep << " sub-steps for the step of " << nominal_dt_
      << " s): the forces blew up (check --set values such as gravity)";
  throw SimulationError(msg.str());
}

// One nominal step: adaptive sub-steps up to step_ × time_step_s (step 0 only evaluates).
void Wcsph::Step() {
  const double target = double(step_) * nominal_dt_;
  clock_.Start();
  while (step_ > 0 && s_.time_s < target) {
    const double remaining = target - s_.time_s;
    if (stop_requested_ && stop_requested_()) throw Cancelled();
    const double safe = SafeDt();
    stats_.dt_safe_s = safe;
    CheckProgress(safe);
    const bool try_optimistic = p_.optimistic_dt && cooldown_ == 0;
    double dt = try_optimistic ? p_.optimistic_factor * safe : safe;
    // The rest of the nominal step in equal parts no longer than dt: no sliver of a last step.
    const double parts = std::max(1.0, std::ceil(remaining / dt * (1 - 1e-9)));
    dt = remaining / parts;
    const bool last = parts == 1;
    const bool optimistic = try_optimistic && dt > safe;
    if (optimistic) Checkpoint();
    clock_.Mark(kControl);
    Substep(dt);
    if (last) s_.time_s = target;
    const double variation = MaxDensityVariation();
    if (optimistic && variation > p_.rollback_threshold) {
      Restore();
      clock_.Mark(kControl);
      ++stats_.rollbacks;
      ++log_rollbacks_;
      cooldown_ = std::size_t(p_.cooldown_steps);
      continue;
    }
    clock_.Mark(kControl);
    if (!optimistic && cooldown_ > 0) --cooldown_;
    ++stats_.substeps;
    stats_.last_dt_s = dt;
    log_dt_min_ = log_substeps_ == 0 ? dt : std::min(log_dt_min_, dt);
    log_dt_max_ = log_substeps_ == 0 ? dt : std::max(log_dt_max_, dt);
    log_variation_max_ = std::max(log_variation_max_, variation);
    ++log_substeps_;
  }
  stats_.time_s = s_.time_s;
  stats_.max_density_variation = MaxDensityVariation();
  WriteOutputs();
  ++step_;
}

void Wcsph::WriteOutputs() {
  const std::size_t n = s_.x.size();
  const float to_cu = float(1 / scale_);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = std::size_t(s_.row[i]);
    out_density_[r] = s_.rho[i];
    out_pressure_[r] = Pressure(s_.rho[i]);
    if (!s_.liquid[i]) {
      out_velocity_[r] = wall_velocity_[r];
      continue;
    }
    out_position_[r] = {s_.x[i] * to_cu, s_.y[i] * to_cu, s_.z[i] * to_cu, out_position_[r].w};
    out_velocity_[r] = {s_.vx[i], s_.vy[i], s_.vz[i], 0.0f};
  }
}

std::vector<float> Wcsph::Density() const { return out_density_; }

std::string Wcsph::TakeStepLog() {
  std::ostringstream s;
  s.precision(9);
  s << "{\"time_s\": " << s_.time_s << ", \"substeps\": " << log_substeps_
    << ", \"dt_min_s\": " << log_dt_min_ << ", \"dt_max_s\": " << log_dt_max_
    << ", \"rollbacks\": " << log_rollbacks_ << ", \"rollbacks_total\": " << stats_.rollbacks
    << ", \"substeps_total\": " << stats_.substeps
    << ", \"max_density_variation\": " << MaxDensityVariation()
    << ", \"max_density_variation_interval\": " << log_variation_max_ << "}";
  log_substeps_ = log_rollbacks_ = 0;
  log_dt_min_ = log_dt_max_ = log_variation_max_ = 0;
  return s.str();
}

std::vector<float> Wcsph::DensityDiffusionRates() const {
  std::vector<float> out(s_.x.size(), 0.0f);
  const float m = float(mass_), scale = 2.0f * float(p_.diffusion_delta * h_ * sound_speed_);
  for (std::int32_t i : process_) {
    if (!s_.liquid[i]) continue;
    float sum = 0;
    for (std::int32_t k = 0; k < list_count_[i]; ++k) {
      const std::int32_t j = list_[i][k];
      if (!s_.liquid[j]) continue;
      const float dx = s_.x[i] - s_.x[j], dy = s_.y[i] - s_.y[j], dz = s_.z[i] - s_.z[j];
      const float f = kernel_.GradientOverR(std::sqrt(dx * dx + dy * dy + dz * dz));
      sum += DensityDiffusionPair(s_.rho[i], s_.rho[j], f, m / s_.rho[j]);
    }
    out[std::size_t(s_.row[i])] = scale * sum;
  }
  return out;
}

std::vector<Float4> Wcsph::XsphVelocities() const {
  const_cast<Wcsph*>(this)->DensityRates();
  std::vector<Float4> out(s_.x.size());
  for (std::size_t i = 0; i < s_.x.size(); ++i)
    if (s_.liquid[i]) out[std::size_t(s_.row[i])] = {xsph_x_[i], xsph_y_[i], xsph_z_[i], 0.0f};
  return out;
}

void Wcsph::SetDensities(const std::vector<float>& density) {
  for (std::size_t i = 0; i < s_.x.size(); ++i) s_.rho[i] = density[std::size_t(s_.row[i])];
  Evaluate();
  WriteOutputs();
}

void Wcsph::SetVelocities(const std::vector<Float4>& velocity) {
  for (std::size_t i = 0; i < s_.x.size(); ++i) {
    if (!s_.liquid[i]) continue;
    const Float4& v = velocity[std::size_t(s_.row[i])];
    s_.vx[i] = v.x;
    s_.vy[i] = v.y;
    s_.vz[i] = v.z;
  }
  Evaluate();
  WriteOutputs();
}

std::string Wcsph::parameters() const {
  std::ostringstream s;
  s.precision(6);
  s << "kernel = Wendland C2, h = " << h_ << " m (h_factor " << p_.h_factor << " x spacing "
    << spacing_m_ << " m" << (p_.spacing_m > 0 ? "" : ", derived") << "), mass = " << mass_
    << " kg, sound_speed = " << sound_speed_ << " m/s (factor " << p_.sound_speed_factor
    << ", c_min " << p_.min_sound_speed_m_s << "), tait_gamma = " << p_.tait_gamma
    << ", cfl = " << p_.cfl << ", integrator = velocity Verlet (kick-drift-kick)"
    << ", density_diffusion = " << p_.density_diffusion << " (delta " << p_.diffusion_delta
    << ", Molteni & Colagrossi 2009)"
    << ", xsph = " << p_.xsph << " (epsilon " << p_.xsph_epsilon << ")"
    << ", viscosity_alpha = " << p_.viscosity_alpha << ", optimistic_dt = " << p_.optimistic_dt
    << " (factor " << p_.optimistic_factor << ", rollback above " << p_.rollback_threshold
    << ", cooldown " << p_.cooldown_steps << " steps)"
    << ", morton_reorder = " << p_.morton_reorder << " (every " << p_.reorder_interval
    << " steps), hydrostatic_start = " << p_.hydrostatic_start
    << ", walls = dynamic boundary particles, nominal_step_s = " << nominal_dt_;
  return s.str();
}

}  // namespace owval::engine::internal
