#pragma once
#include <string>

namespace grainlab::cli {

struct DieModelArgs {
  double f = 0.2, eps = 0.7;
  bool json = false;
  std::string plot_dir;  // non-empty: also write the Fig. 2.7 report there
};

int die_model_command(const DieModelArgs& a);

}  // namespace grainlab::cli
