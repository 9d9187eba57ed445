#pragma once
// The rules validate() (run_config.h) applies, as data: for each field, by its dotted path, the text its error
// message gives ("must be in [0, 1]", "<= poet.mc_high", "required in mode ES_ALONE"), recorded by running the
// validator's own checks in a mode that records each rule instead of stopping at the first problem. The config
// reference (config_reference.h) shows them, so a page cannot drift from the checks.

#include <string>
#include <vector>

#include "poet.pb.h"

namespace poet {

struct ConfigRule {
  std::string path;  // the field's dotted path as error messages name it: "es.l2_coeff"
  std::string rule;  // the rule as the error message states it, without the value: "must be in [0, 1]"
  // The modes whose configs the rule is checked in, in the enum's order: all four for a rule of every config.
  std::vector<pb::RunConfig::Mode> modes;
};

// Every rule of validate(), recorded over a config of each mode, in the order the checks run (the schema's);
// a rule recorded in several modes appears once, with those modes. Excludes the fields inside an environment
// target (es_alone.target, direct_path.target): env_def_from_proto checks those (common/formats/envgen/env_proto.h),
// and the target's own rule says so.
std::vector<ConfigRule> config_rules();

}  // namespace poet
