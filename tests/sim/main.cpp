// isocam_gcode_sim: measures what a posted ball-end program really cuts.
// See gcode_sim.h for what is measured; `isocam_gcode_sim --help` for usage.
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <Standard_Failure.hxx>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "gcode_sim.h"

namespace {

const char* kUsage =
    "usage: isocam_gcode_sim --brep MODEL.brep --faces 1[,2...] --radius R\n"
    "                        (--gcode FILE.ngc [--rs274 PATH] [--tool-table FILE] | --canon FILE)\n"
    "                        [--spacing 0.05] [--threads 2] [--scallop H] [--max-residual 0.5]\n"
    "                        [--reach-margin 0] [--reach-tol 1e-4] [--reach-from-above 1]\n"
    "                        [--arc-sag 1e-5] [--cell 0.5]\n"
    "                        [--map FILE [--map-step 0.2]] [--canon-out FILE] [--rapid-rate 5000]\n"
    "Sweeps a ball of radius R (mm) along the program's moves (tool-tip\n"
    "coordinates, ball centre R above the tip) and prints a JSON summary: the\n"
    "most material left on reachable points of the picked faces (FreeCAD's\n"
    "FaceN numbers; reachable: the ball touching the point, and with\n"
    "--reach-from-above 1 that ball lifted straight up, hold no model point),\n"
    "the deepest overcut on any face (rapids included, and\n"
    "rapids alone), counts, lengths, the machine time at the program's feeds\n"
    "and --rapid-rate (mm/min, no acceleration). --map writes 'x y residual' lines.\n";

double positive(const std::string& name, const std::string& v, bool allow_zero = false) {
  double x = 0;
  try {
    std::size_t used = 0;
    x = std::stod(v, &used);
    if (used != v.size()) throw std::invalid_argument(v);
  } catch (const std::logic_error&) {
    throw std::runtime_error(name + ": not a number: '" + v + "'");
  }
  if (!(allow_zero ? x >= 0 : x > 0))
    throw std::runtime_error(name + " must be " + (allow_zero ? ">= 0" : "> 0") + ", got " + v);
  return x;
}

std::vector<int> face_list(const std::string& v) {
  std::vector<int> faces;
  std::stringstream in(v);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item.rfind("Face", 0) == 0) item = item.substr(4);
    const double f = positive("--faces", item);
    if (f != static_cast<int>(f)) throw std::runtime_error("--faces: not a face number: " + item);
    faces.push_back(static_cast<int>(f));
  }
  if (faces.empty()) throw std::runtime_error("--faces: no face given");
  return faces;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

int run(int argc, char** argv) {
  std::map<std::string, std::string> a;
  for (int i = 1; i < argc; ++i) {
    const std::string key = argv[i];
    if (key == "--help" || key == "-h") {
      std::cout << kUsage;
      return 0;
    }
    if (key.rfind("--", 0) != 0 || i + 1 >= argc)
      throw std::runtime_error("bad argument '" + key + "' (each option takes a value)\n" + kUsage);
    a[key] = argv[++i];
  }
  static const char* known[] = {
      "--brep",         "--faces",        "--radius",    "--gcode",      "--rs274",
      "--tool-table",   "--canon",        "--spacing",   "--threads",    "--scallop",
      "--max-residual", "--reach-margin", "--reach-tol", "--arc-sag",    "--cell",
      "--map",          "--map-step",     "--canon-out", "--rapid-rate", "--reach-from-above"};
  for (const auto& [k, v] : a) {
    bool ok = false;
    for (const char* n : known) ok = ok || k == n;
    if (!ok) throw std::runtime_error("unknown option " + k + "\n" + kUsage);
  }
  for (const char* need : {"--brep", "--faces", "--radius"})
    if (!a.count(need)) throw std::runtime_error(std::string("missing ") + need + "\n" + kUsage);
  if (a.count("--gcode") == a.count("--canon"))
    throw std::runtime_error(std::string("give exactly one of --gcode and --canon\n") + kUsage);

  gsim::Options o;
  o.ball_radius = positive("--radius", a["--radius"]);
  if (a.count("--threads")) o.threads = static_cast<int>(positive("--threads", a["--threads"]));
  if (a.count("--scallop")) o.scallop = positive("--scallop", a["--scallop"]);
  if (a.count("--max-residual")) o.max_residual = positive("--max-residual", a["--max-residual"]);
  if (a.count("--reach-margin"))
    o.reach_margin = positive("--reach-margin", a["--reach-margin"], true);
  if (a.count("--reach-tol")) o.reach_tol = positive("--reach-tol", a["--reach-tol"], true);
  if (a.count("--reach-from-above")) {
    const std::string& v = a["--reach-from-above"];
    if (v != "0" && v != "1")
      throw std::runtime_error("--reach-from-above must be 0 or 1, got " + v);
    o.from_above = v == "1";
  }
  if (a.count("--cell")) o.cell = positive("--cell", a["--cell"]);
  if (a.count("--rapid-rate")) o.rapid_rate = positive("--rapid-rate", a["--rapid-rate"]);
  const double spacing = a.count("--spacing") ? positive("--spacing", a["--spacing"]) : 0.05;
  const double arc_sag = a.count("--arc-sag") ? positive("--arc-sag", a["--arc-sag"]) : 1e-5;
  const std::vector<int> picked = face_list(a["--faces"]);

  const auto t0 = std::chrono::steady_clock::now();
  TopoDS_Shape shape;
  {
    std::ifstream in(a["--brep"]);
    if (!in) throw std::runtime_error("cannot open B-rep file " + a["--brep"]);
    BRep_Builder builder;
    BRepTools::Read(shape, in, builder);
    if (shape.IsNull()) throw std::runtime_error("no shape in B-rep file " + a["--brep"]);
  }
  const int face_count = static_cast<int>(gsim::faces_of(shape).size());
  for (int f : picked)
    if (f > face_count)
      throw std::runtime_error("--faces: face " + std::to_string(f) + " does not exist: " +
                               a["--brep"] + " has " + std::to_string(face_count) + " faces");

  std::string canon;
  if (a.count("--gcode")) {
    canon = gsim::run_rs274(a.count("--rs274") ? a["--rs274"] : "rs274", a["--gcode"],
                            a.count("--tool-table") ? a["--tool-table"] : "");
    if (a.count("--canon-out")) {
      std::ofstream out(a["--canon-out"]);
      if (!(out << canon)) throw std::runtime_error("cannot write " + a["--canon-out"]);
    }
  } else {
    std::ifstream in(a["--canon"]);
    if (!in) throw std::runtime_error("cannot open canonical file " + a["--canon"]);
    std::stringstream ss;
    ss << in.rdbuf();
    canon = ss.str();
  }
  const double t_rs274 = seconds_since(t0);
  std::istringstream cin_(canon);
  const gsim::Program program = gsim::parse_canon(cin_, arc_sag);
  if (program.moves.empty()) throw std::runtime_error("the program has no moves");

  const auto t1 = std::chrono::steady_clock::now();
  const std::vector<gsim::Sample> samples = gsim::sample_faces(shape, picked, spacing, o.threads);
  const double t_sample = seconds_since(t1);
  const auto t2 = std::chrono::steady_clock::now();
  const gsim::Result result = gsim::measure(samples, program, o);
  const double t_measure = seconds_since(t2);

  gsim::write_json(std::cout, samples, program, o, result, spacing, picked, face_count);
  if (a.count("--map")) {
    std::ofstream out(a["--map"]);
    gsim::write_map(out, samples, result,
                    a.count("--map-step") ? positive("--map-step", a["--map-step"]) : 0.2);
    if (!out) throw std::runtime_error("cannot write " + a["--map"]);
  }
  std::cerr << "isocam_gcode_sim: read " << t_rs274 << " s, sampled " << samples.size()
            << " points in " << t_sample << " s, measured in " << t_measure << " s\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const Standard_Failure& e) {
    std::cerr << "isocam_gcode_sim: OpenCASCADE: " << e.GetMessageString() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "isocam_gcode_sim: " << e.what() << "\n";
  }
  return 2;
}
