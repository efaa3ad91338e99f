#pragma once
// Sibernetic text rows and header as WriteSiberneticText writes them (6 significant digits), shared
// with the streaming writer so that both produce the same bytes.
#include <string>
#include <vector>

#include "owval/trajectory/trajectory.hpp"

namespace owval::internal {

void AppendNumber(std::string& out, float value);
// "x\\ty\\tz\\ttype\\n"
void AppendRow(std::string& out, const float* xyz, float type);
// The 11 header lines: box, elastic/liquid/boundary counts of `type`, time step, log step.
std::string TextHeader(const Box& box, const std::vector<float>& type, double time_step_s,
                       int log_step);

}  // namespace owval::internal
