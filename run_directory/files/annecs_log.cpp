#include "run_directory/files/annecs_log.h"

#include <vector>

namespace poet {

std::string annecs_header() { return "iteration,annecs_at_admission,annecs_at_archiving\n"; }

std::string annecs_line(int iteration, const Annecs& annecs) {
  return std::to_string(iteration) + "," + std::to_string(annecs.at_admission) + "," +
         std::to_string(annecs.at_archiving) + "\n";
}

std::string annecs_text(const RunState& state) {
  std::string text = annecs_header();
  const std::vector<Annecs> series = annecs_over_time(state);
  for (size_t t = 0; t < series.size(); ++t) text += annecs_line(static_cast<int>(t), series[t]);
  return text;
}

}  // namespace poet
