#include "finishing/face_failure.h"

#include <Standard_Failure.hxx>

#include "finishing/coverage.h"
#include "isocam/errors.h"

namespace isocam {

std::optional<std::string> face_failure(int face, const std::function<void()>& fn) {
  std::string why;
  try {
    fn();
    return std::nullopt;
  } catch (const GeometryError& e) {
    why = e.what();
  } catch (const Standard_Failure& e) {
    why = std::string("OpenCASCADE failed: ") + e.GetMessageString();
  }
  const std::string label = face_label(face);
  if (why.compare(0, label.size(), label) == 0) return why;
  return label + ": " + why;
}

std::string skipped_face_warning(const std::string& reason, bool in_model) {
  return reason + "; skipped: no path on this face" +
         (in_model ? std::string(" (the others are finished)")
                   : std::string(", and it is not protected from the tool"));
}

void throw_every_face_failed(const std::vector<std::string>& reasons) {
  std::string m = "no picked face could be finished: ";
  for (std::size_t i = 0; i < reasons.size(); ++i) m += (i ? "; " : "") + reasons[i];
  throw GeometryError(m);
}

}  // namespace isocam
