#pragma once
// The numbers of the evolution strategy (spec §2). The defaults are the schema's (EsConfig in proto/poet.proto,
// the reference's run script), the one home of every default; the coordinator fills them from RunConfig.es.

#include "schema_defaults.h"

namespace poet {

struct EsSettings {
  int perturbations = schema_defaults::es_config::perturbations;  // n mirrored pairs: 2n rollouts per ES step
  double init_sigma = schema_defaults::es_config::init_sigma;
  double sigma_decay = schema_defaults::es_config::sigma_decay;
  double sigma_floor = schema_defaults::es_config::sigma_floor;
  double init_lr = schema_defaults::es_config::init_lr;
  double lr_decay = schema_defaults::es_config::lr_decay;
  double lr_floor = schema_defaults::es_config::lr_floor;
  double l2_coeff = schema_defaults::es_config::l2_coeff;  // λ in Adam on −g + λθ and in the SGD proposal
  double adam_beta1 = schema_defaults::es_config::adam_beta1;
  double adam_beta2 = schema_defaults::es_config::adam_beta2;
  double adam_epsilon = schema_defaults::es_config::adam_epsilon;
  bool normalize_grads_by_sigma = schema_defaults::es_config::normalize_grads_by_sigma;

  bool operator==(const EsSettings&) const = default;  // outcomes computed with equal settings are reused
};

}  // namespace poet
