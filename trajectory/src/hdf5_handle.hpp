#pragma once
// An HDF5 identifier closed when it leaves scope.
#include <hdf5.h>

#include <mutex>

namespace owval::internal {

class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// Call before any other libhdf5 call. Silences libhdf5's error printing (owval reports errors
// itself) and, the first time, keeps libhdf5 from closing files in an exit handler: after a
// failed write (a full disk) libhdf5 1.10 keeps the file open, and closing it again at exit
// crashed in H5F__close_cb (issue 18 item 3). owval closes every file it opens itself.
// Debian's libhdf5 is the serial build: not thread-safe. Every owval entry into libhdf5 holds this
// lock (sgd's parallel finite differences read two trajectories at once); ReadHdf5 also forks its
// contained dry run under it, so no other thread is inside libhdf5 at the fork.
inline std::recursive_mutex& Hdf5Mutex() {
  static std::recursive_mutex mutex;
  return mutex;
}

inline void PrepareHdf5() {
  static const bool once = [] {
    H5dont_atexit();  // fails harmlessly when the library was already initialised
    return true;
  }();
  (void)once;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

}  // namespace owval::internal
