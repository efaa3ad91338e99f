#include "owval/pipeline/gradcheck_request.hpp"

#include <sstream>
#include <utility>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/sgd/gradcheck.hpp"
#include "owval/sgd/gradient_fit.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::pipeline {
namespace {

// Of demo1's two loss groups, those the reference holds (one_sprig has no liquid, free_fall no
// elastic particle): each one's centroid is a term of the end-to-end loss.
std::vector<std::string> CentroidLossGroups(const Trajectory& header, const std::string& file) {
  std::vector<std::string> groups;
  for (const auto& [name, kind] :
       {std::pair{"elastic", ParticleKind::kElastic}, std::pair{"liquid", ParticleKind::kLiquid}})
    if (header.count(kind) > 0) groups.push_back(name);
  if (groups.empty())
    throw InputError(file, 0, "no elastic or liquid particle: nothing to take a loss on");
  return groups;
}

}  // namespace

GradCheckResult RunGradCheckRequest(GradCheckRequest r) {
  engine::GradCheckOptions& o = r.options;
  if (!r.output.empty()) {
    CheckOutputPath(r.output);
    CheckOutputIsNotAnInput(r.output, {o.end_to_end_config, r.reference});
  }
  const std::filesystem::path demo1 = r.shared_reference / "demo1";
  if (o.end_to_end_config.empty()) {
    o.end_to_end_config = (demo1 / "configuration").string();
    if (r.reference.empty()) r.reference = (demo1 / "position_buffer.txt").string();
  }
  if (!r.reference.empty()) {  // demo1's fit loss: the centroids against a reference run
    const auto reference = OpenFrameSource(r.reference, {.quiet = true});  // up to the steps only
    o.end_to_end_loss = sgd::GroupCentroidLoss(
        *reference, CentroidLossGroups(reference->header(), r.reference), o.end_to_end_steps, 1.0);
    o.end_to_end_loss_name = "centroids vs " + r.reference;
  }
  GradCheckResult result;
  result.summary = engine::RunGradCheck(o);
  result.json = sgd::GradCheckJson(result.summary, o);
  if (!r.output.empty()) WriteFileAtomically(r.output, result.json.dump(2) + "\n");
  return result;
}

std::string GradCheckResult::ToText() const {
  std::ostringstream out;
  for (const engine::GradCheckTest& t : summary.tests)
    out << (t.pass ? "pass " : "FAIL ") << t.name << ": fd " << t.finite_difference << ", analytic "
        << t.analytic << ", relative error " << t.relative_error << "\n";
  out << summary.BriefReport() << "\n";
  return out.str();
}

}  // namespace owval::pipeline
