#pragma once
// Binary solver state for checkpoints (Solver::SaveState / RestoreState): plain values and
// vectors of trivially copyable types in the machine's byte order, each vector preceded by its
// length. A checkpoint is read back by the same build on the same kind of machine; the header
// (magic, format version, backend, particle count, steps done) refuses anything else.
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "owval/base/errors.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

constexpr char kStateMagic[8] = {'O', 'W', 'V', 'S', 'T', 'A', 'T', 'E'};
constexpr std::uint32_t kStateFormatVersion = 1;

class StateWriter {
 public:
  explicit StateWriter(std::string* out) : out_(out) {}
  template <typename T>
  void Put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_->append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  template <typename T>
  void Put(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    Put(std::uint64_t(values.size()));
    out_->append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  void Put(const std::string& text) {
    Put(std::uint64_t(text.size()));
    out_->append(text);
  }

 private:
  std::string* out_;
};

class StateReader {
 public:
  StateReader(const std::string& in, std::string source) : in_(in), source_(std::move(source)) {}
  template <typename T>
  void Get(T* value) {
    static_assert(std::is_trivially_copyable_v<T>);
    std::memcpy(value, Take(sizeof(T)), sizeof(T));
  }
  template <typename T>
  void Get(std::vector<T>* values) {
    std::uint64_t n = 0;
    Get(&n);
    if (n > (in_.size() - pos_) / sizeof(T)) Fail("a vector longer than the file");
    values->resize(n);
    if (n) std::memcpy(values->data(), Take(n * sizeof(T)), n * sizeof(T));
  }
  void Get(std::string* text) {
    std::uint64_t n = 0;
    Get(&n);
    if (n > in_.size() - pos_) Fail("a string longer than the file");
    text->assign(Take(n), n);
  }
  // Vectors whose length the solver fixes (per particle, per neighbour slot).
  template <typename T>
  void GetSized(std::vector<T>* values, std::size_t expected) {
    Get(values);
    if (values->size() != expected)
      Fail("a vector of " + std::to_string(values->size()) + " values where " +
           std::to_string(expected) + " were expected");
  }
  bool done() const { return pos_ == in_.size(); }
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(source_, 0, "checkpoint state: " + what);
  }

 private:
  const char* Take(std::size_t n) {
    if (n > in_.size() - pos_) Fail("truncated");
    const char* p = in_.data() + pos_;
    pos_ += n;
    return p;
  }
  const std::string& in_;
  std::string source_;
  std::size_t pos_ = 0;
};

inline void PutStateHeader(StateWriter& w, const std::string& backend, std::uint64_t particles,
                           std::uint64_t steps_done) {
  for (char c : kStateMagic) w.Put(c);
  w.Put(kStateFormatVersion);
  w.Put(backend);
  w.Put(particles);
  w.Put(steps_done);
}

// Checks the header against this solver; returns the steps done.
inline std::uint64_t GetStateHeader(StateReader& r, const std::string& backend,
                                    std::uint64_t particles) {
  char magic[8];
  for (char& c : magic) r.Get(&c);
  if (std::memcmp(magic, kStateMagic, sizeof magic) != 0) r.Fail("not an owval solver state");
  std::uint32_t version = 0;
  r.Get(&version);
  if (version != kStateFormatVersion)
    r.Fail("format version " + std::to_string(version) + ", this build reads " +
           std::to_string(kStateFormatVersion));
  std::string name;
  r.Get(&name);
  if (name != backend) r.Fail("saved by backend " + name + ", not " + backend);
  std::uint64_t n = 0, steps = 0;
  r.Get(&n);
  if (n != particles)
    r.Fail(std::to_string(n) + " particles, the configuration has " + std::to_string(particles));
  r.Get(&steps);
  return steps;
}

// The particle state every solver carries, in its checkpoint: one order for writing and reading.
inline void PutParticleState(StateWriter& w, const ParticleState& s) {
  w.Put(s.position), w.Put(s.velocity), w.Put(s.acceleration), w.Put(s.last_acceleration);
  w.Put(s.density), w.Put(s.pressure), w.Put(s.neighbours), w.Put(s.moving), w.Put(s.active);
}

// Reads what PutParticleState wrote for `s->size()` particles; every index must name one of them.
inline void GetParticleState(StateReader& r, ParticleState* s) {
  const std::size_t n = s->size();
  r.GetSized(&s->position, n), r.GetSized(&s->velocity, n), r.GetSized(&s->acceleration, n);
  r.GetSized(&s->last_acceleration, n), r.GetSized(&s->density, n), r.GetSized(&s->pressure, n);
  r.GetSized(&s->neighbours, n * kSlots), r.Get(&s->moving), r.Get(&s->active);
  for (const std::vector<std::int32_t>* list : {&s->moving, &s->active})
    for (std::int32_t i : *list)
      if (i < 0 || std::size_t(i) >= n) r.Fail("a particle index out of range");
  for (const Neighbour& slot : s->neighbours)
    if (slot.index < -1 || slot.index >= std::int64_t(n)) r.Fail("a neighbour out of range");
}

}  // namespace owval::engine::internal
