#pragma once
// An HDF5 identifier that closes itself when it goes out of scope (for the readers and writers that use
// the C API directly).
#include <hdf5.h>

namespace grainlab {

struct H5Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  H5Handle(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  H5Handle(H5Handle&& o) noexcept : id(o.id), close(o.close) { o.id = -1; }
  ~H5Handle() {
    if (id >= 0) close(id);
  }
};

}  // namespace grainlab
