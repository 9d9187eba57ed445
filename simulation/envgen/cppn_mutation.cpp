#include "simulation/envgen/cppn_mutation.h"

#include <algorithm>
#include <cmath>

#include "simulation/envgen/cppn_course.h"

namespace poet {
namespace {

double clamp_param(double v) { return std::clamp(v, -kCppnParamLimit, kCppnParamLimit); }

// Each structural mutation returns whether it changed the genome (nothing to split or delete: no draw, no change).
bool add_node(CppnGenome& g, RandomStream& stream) {
  if (g.connections.empty()) return false;
  const auto split = g.connections.begin() + stream.uniform_int(0, static_cast<int64_t>(g.connections.size()));
  const CppnConnection old = *split;
  g.connections.erase(split);
  const int id = g.nodes.back().id + 1;  // nodes are sorted by id
  const auto activation = kCppnActivations[stream.uniform_int(0, std::size(kCppnActivations))];
  const double bias = clamp_param(kCppnBiasStddev * stream.normal());
  g.nodes.push_back({id, CppnRole::kHidden, activation, bias});
  g.connections.push_back({old.from, id, 1.0});
  g.connections.push_back({id, old.to, old.weight});
  canonicalize(g);
  return true;
}

bool delete_node(CppnGenome& g, RandomStream& stream) {
  std::vector<int> hidden;
  for (const CppnNode& n : g.nodes)
    if (n.role == CppnRole::kHidden) hidden.push_back(n.id);
  if (hidden.empty()) return false;
  const int id = hidden[static_cast<size_t>(stream.uniform_int(0, static_cast<int64_t>(hidden.size())))];
  std::erase_if(g.nodes, [&](const CppnNode& n) { return n.id == id; });
  std::erase_if(g.connections, [&](const CppnConnection& c) { return c.from == id || c.to == id; });
  return true;
}

void perturb(double& v, RandomStream& stream) {
  if (stream.uniform01() < kCppnPerturbProbability) v = clamp_param(v + kCppnPerturbStddev * stream.normal());
}

}  // namespace

CppnGenome draw_cppn_child(const CppnGenome& parent, RandomStream& stream, CppnStructuralMutation* made) {
  CppnGenome child = parent;
  const double r = stream.uniform01();
  CppnStructuralMutation kind = CppnStructuralMutation::kNone;
  if (r < kCppnAddNodeProbability) {
    if (add_node(child, stream)) kind = CppnStructuralMutation::kAddNode;
  } else if (r < kCppnAddNodeProbability + kCppnDeleteNodeProbability) {
    if (delete_node(child, stream)) kind = CppnStructuralMutation::kDeleteNode;
  }
  for (CppnConnection& c : child.connections) perturb(c.weight, stream);
  for (CppnNode& n : child.nodes)
    if (n.role != CppnRole::kInput) perturb(n.bias, stream);
  if (made) *made = kind;
  return child;
}

bool normalize_cppn_rise(CppnGenome& child, RandomStream& stream) {
  const std::vector<double> relief = cppn_relief(child);
  if (!std::all_of(relief.begin(), relief.end(), [](double h) { return std::isfinite(h); })) return false;
  const double rise = std::abs(*std::max_element(relief.begin(), relief.end()));
  if (rise == 0) return false;
  if (rise < kCppnMinRise) child.scale *= stream.uniform(kCppnLowRiseTo[0], kCppnLowRiseTo[1]) / rise;
  if (rise > kCppnMaxRise) child.scale *= stream.uniform(kCppnHighRiseTo[0], kCppnHighRiseTo[1]) / rise;
  return true;
}

CppnGenome mutate_cppn(const CppnGenome& parent, RandomStream& stream) {
  for (int draw = 0; draw < kCppnMaxDraws; ++draw) {
    CppnGenome child = draw_cppn_child(parent, stream);
    if (child == parent || !has_input_output_path(child)) continue;
    // the normalisation changes only the scale, so the child still differs from its parent
    if (normalize_cppn_rise(child, stream) && !validate_cppn_course(child)) return child;
  }
  return parent;
}

CppnGenome first_cppn_genome(RandomStream& stream) {
  const double weight = clamp_param(kCppnSeedWeightStddev * stream.normal());
  const double bias = clamp_param(kCppnBiasStddev * stream.normal());
  return cppn_seed_genome(weight, bias);
}

}  // namespace poet
