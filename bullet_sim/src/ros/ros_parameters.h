// The parameter server as the core's ParameterSource: what plugins read at run time (ros_control's controllers
// and pid_gains) comes from here, as a ParameterTree.
#pragma once

#include "bullet_sim/plugins/parameter_tree.h"

namespace bullet_sim {

class RosParameters : public ParameterSource {
 public:
  /// The parameters under `ns` as they are now; an empty tree when there are none.
  ParameterTree fetch(const std::string& ns) const override;
};

}  // namespace bullet_sim
