#pragma once
// The numbers of the evolution strategy (spec §2). Defaults are the reference's run script; the coordinator
// fills them from RunConfig.es.

namespace poet {

struct EsSettings {
  int perturbations = 256;  // n mirrored pairs: 2n rollouts per ES step
  double init_sigma = 0.1;
  double sigma_decay = 0.999;
  double sigma_floor = 0.01;
  double init_lr = 0.01;
  double lr_decay = 0.9999;
  double lr_floor = 0.001;
  double l2_coeff = 0.01;  // λ in Adam on −g + λθ and in the SGD proposal
  double adam_beta1 = 0.9;
  double adam_beta2 = 0.999;
  double adam_epsilon = 1e-8;
  bool normalize_grads_by_sigma = true;

  bool operator==(const EsSettings&) const = default;  // outcomes computed with equal settings are reused
};

}  // namespace poet
