#include "python/course_spec.h"

#include <filesystem>
#include <stdexcept>

#include "common/formats/envgen/env_json.h"
#include "simulation/envgen/named_courses.h"

namespace poet::python {

CourseSpec course_from_name_or_file(const std::string& course) {
  if (std::optional<EnvEncoding> named = named_course(course)) return {*named, std::nullopt};
  std::error_code ec;
  if (!std::filesystem::exists(course, ec))
    throw std::invalid_argument("course '" + course +
                                "': not a named course (flat, r1, r3, hard, hardcore-like) nor an existing file");
  Expected<EnvDef> def = load_env_def(course);
  if (!def) throw std::invalid_argument(def.error());
  return {def->encoding, def->seed};
}

CourseSpec course_from_json_text(const std::string& text) {
  Expected<EnvDef> def = parse_env_def(text);
  if (!def) throw std::invalid_argument("course: " + def.error());
  return {def->encoding, def->seed};
}

}  // namespace poet::python
