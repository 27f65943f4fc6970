#pragma once
// What a model built from a valid input may still do that its author did not mean: found at the
// start of `run`, `check` and `fos`, printed as warnings (the run goes on).
#include "tsuchi/model/config.hpp"
#include "tsuchi/model/model.hpp"

#include <string>
#include <vector>

namespace tsuchi {

template <int D>
std::vector<std::string> start_warnings(const Config& c, const Model<D>& m);

extern template std::vector<std::string> start_warnings<2>(const Config&, const Model<2>&);
extern template std::vector<std::string> start_warnings<3>(const Config&, const Model<3>&);

}  // namespace tsuchi
