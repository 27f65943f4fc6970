#include "tsuchi/model/config.hpp"

namespace tsuchi {

const char* to_string(Scheme s) {
  switch (s) {
    case Scheme::USF: return "USF";
    case Scheme::USL: return "USL";
    case Scheme::MUSL: return "MUSL";
  }
  return "?";
}

const char* to_string(ShapeKind s) {
  switch (s) {
    case ShapeKind::Linear: return "linear";
    case ShapeKind::UGimp: return "ugimp";
    case ShapeKind::Gimp: return "gimp";
  }
  return "?";
}

const char* to_string(VelocityTransfer t) {
  switch (t) {
    case VelocityTransfer::Flip: return "flip";
    case VelocityTransfer::Apic: return "apic";
  }
  return "?";
}

const char* to_string(AntiLocking a) {
  switch (a) {
    case AntiLocking::None: return "none";
    case AntiLocking::Cell: return "cell";
    case AntiLocking::Node: return "node";
    case AntiLocking::Bbar: return "bbar";
  }
  return "?";
}

}  // namespace tsuchi
