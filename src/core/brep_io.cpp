#include "isocam/brep_io.h"

#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <fstream>
#include <sstream>

#include "brep_guard.h"
#include "isocam/errors.h"

namespace isocam {
namespace {

// The text as a stream buffer that counts the reads past its end.
// OpenCASCADE's reader, on text whose tokens are out of step with what it
// expects, can loop for ever at the end of the text: a loop such as
// "while (val > 0) { ...; in >> val; }" keeps val when the read fails. So
// the stream throws on a failed read (failbit in its exception mask; a valid
// text is read without one), and this buffer throws if the reader clears
// the stream and reads on past the end regardless (a valid text is read
// with a handful of such reads).
class BoundedBuffer : public std::streambuf {
 public:
  explicit BoundedBuffer(const std::string& text) {
    char* p = const_cast<char*>(text.data());
    setg(p, p, p + text.size());
  }
  struct ReadPastEnd {};
  std::size_t offset() const { return static_cast<std::size_t>(gptr() - eback()); }

 protected:
  int_type underflow() override {
    if (++reads_at_end_ > kMaxReadsAtEnd) throw ReadPastEnd();
    return traits_type::eof();
  }

 private:
  static constexpr int kMaxReadsAtEnd = 1000;
  int reads_at_end_ = 0;
};

}  // namespace

TopoDS_Shape read_brep(const std::string& text) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw InvalidArgument("brep: the B-rep text is empty");
  detail::check_brep_text(text);
  TopoDS_Shape shape;
  BoundedBuffer buffer(text);
  try {
    std::istream in(&buffer);
    in.exceptions(std::ios::badbit | std::ios::failbit);
    BRep_Builder builder;
    BRepTools::Read(shape, in, builder);
  } catch (const std::ios_base::failure&) {
    throw InvalidArgument("brep: unreadable B-rep text (a value is missing or malformed at byte " +
                          std::to_string(buffer.offset()) + " of " + std::to_string(text.size()) +
                          ")");
  } catch (const BoundedBuffer::ReadPastEnd&) {
    throw InvalidArgument(
        "brep: the text ends before the shapes it describes (the reader ran past "
        "its last byte, " +
        std::to_string(text.size()) + ")");
  } catch (const Standard_Failure& e) {
    throw InvalidArgument(std::string("brep: unreadable B-rep text (") + e.GetMessageString() +
                          ")");
  }
  if (shape.IsNull()) throw InvalidArgument("brep: unreadable B-rep text (no shape in it)");
  return shape;
}

TopoDS_Shape read_brep_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidArgument("brep: cannot open file " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  return read_brep(ss.str());
}

std::vector<TopoDS_Face> faces_of(const TopoDS_Shape& shape) {
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(shape, TopAbs_FACE, map);
  std::vector<TopoDS_Face> faces;
  faces.reserve(static_cast<std::size_t>(map.Extent()));
  for (int i = 1; i <= map.Extent(); ++i) faces.push_back(TopoDS::Face(map(i)));
  return faces;
}

}  // namespace isocam
