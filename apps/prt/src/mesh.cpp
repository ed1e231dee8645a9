// Mesh input, validation and the built-in scenes (see mesh.hpp).
#include "atmosh/prt/mesh.hpp"

#include <tiny_obj_loader.h>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <iterator>
#include <sstream>
#include <tuple>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <utility>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"

namespace atmosh::prt {

namespace {
constexpr double kPi = std::numbers::pi;

std::string lower_ext(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

// tinyobjloader reads an unparsable coordinate ("nan", "inf", "1e999") as 0 without a
// warning; check the vertex lines first so that such a file is rejected, not altered.
void check_obj_vertices(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::size_t lineno = 0, vertex = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.size() < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) continue;
    const char* p = line.c_str() + 2;
    for (int k = 0; k < 3; ++k) {
      char* end = nullptr;
      const double x = std::strtod(p, &end);
      if (end == p || !std::isfinite(x))
        throw InputError(file.string() + ": vertex " + std::to_string(vertex) + " (line " + std::to_string(lineno) +
                         ") is not three finite numbers: '" + line + "'");
      p = end;
    }
    ++vertex;
  }
}

Mesh load_obj(const std::filesystem::path& file) {
  check_obj_vertices(file);
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  const std::string base = file.parent_path().string() + "/";
  if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, file.c_str(), base.c_str(), true)) {
    std::string msg = err;
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    throw InputError(file.string() + ": not a readable OBJ file (" + msg + ")");
  }
  Mesh m;
  m.name = file.string();
  const std::size_t nv = attrib.vertices.size() / 3;
  m.positions.resize(nv);
  for (std::size_t i = 0; i < nv; ++i)
    m.positions[i] = {attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]};
  std::vector<double> asum(nv, 0.0);
  std::vector<int> acount(nv, 0);
  for (const auto& sh : shapes) {
    std::size_t off = 0;
    for (std::size_t f = 0; f < sh.mesh.num_face_vertices.size(); ++f) {
      const int fv = sh.mesh.num_face_vertices[f];
      if (fv != 3) throw InputError(m.name + ": face " + std::to_string(f) + " has " + std::to_string(fv) + " vertices after triangulation");
      std::array<std::uint32_t, 3> t{};
      for (int k = 0; k < 3; ++k) {
        const int idx = sh.mesh.indices[off + k].vertex_index;
        if (idx < 0 || static_cast<std::size_t>(idx) >= nv)
          throw InputError(m.name + ": face " + std::to_string(f) + " names vertex " + std::to_string(idx) + " of " + std::to_string(nv));
        t[k] = static_cast<std::uint32_t>(idx);
      }
      m.triangles.push_back(t);
      const int mat = f < sh.mesh.material_ids.size() ? sh.mesh.material_ids[f] : -1;
      if (mat >= 0 && static_cast<std::size_t>(mat) < materials.size()) {
        const auto& kd = materials[mat].diffuse;
        const double a = (kd[0] + kd[1] + kd[2]) / 3.0;
        for (auto v : t) asum[v] += a, acount[v]++;
      }
      off += 3;
    }
  }
  if (std::any_of(acount.begin(), acount.end(), [](int c) { return c > 0; })) {
    m.albedo.assign(nv, 0.8);
    for (std::size_t i = 0; i < nv; ++i)
      if (acount[i] > 0) m.albedo[i] = std::clamp(asum[i] / acount[i], 0.0, 1.0);
  }
  return m;
}

// ---- PLY validation -------------------------------------------------------------------
// The mesh library trusts a PLY header's element counts and list lengths: a truncated
// file aborts inside its triangulation and a binary header with no data reads past
// the end. So the whole file is walked here first, header and data, without trusting
// any count: every row must lie inside the file, list lengths must be 3..kMaxPolygon,
// x/y/z finite, vertex indices in range. Triangle strips (element "tristrips") are refused:
// the mesh library (assimp 5.2) loses the first triangle of a strip (a 4-vertex strip over a
// square came back as one triangle) and leaks memory on every strip longer than three.
constexpr std::size_t kMaxPolygon = 1024;
constexpr std::uint64_t kMaxElements = std::uint64_t{1} << 31;

struct PlyProperty {
  std::string name;
  int size = 0;           // bytes of the scalar, or of each list item
  bool is_float = false, is_signed = false;
  bool list = false;
  int count_size = 0;     // bytes of the list length
  bool count_signed = false;
};
struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> props;
};

bool ply_type(const std::string& t, int& size, bool& is_float, bool& is_signed) {
  static const std::map<std::string, std::tuple<int, bool, bool>> types = {
      {"char", {1, false, true}},   {"int8", {1, false, true}},    {"uchar", {1, false, false}},
      {"uint8", {1, false, false}}, {"short", {2, false, true}},   {"int16", {2, false, true}},
      {"ushort", {2, false, false}}, {"uint16", {2, false, false}}, {"int", {4, false, true}},
      {"int32", {4, false, true}},  {"uint", {4, false, false}},   {"uint32", {4, false, false}},
      {"float", {4, true, true}},   {"float32", {4, true, true}},  {"double", {8, true, true}},
      {"float64", {8, true, true}}};
  const auto it = types.find(t);
  if (it == types.end()) return false;
  std::tie(size, is_float, is_signed) = it->second;
  return true;
}

class PlyCheck {
 public:
  explicit PlyCheck(const std::filesystem::path& file) : file_(file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) fail("cannot be read");
    data_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }

  void run() {
    read_header();
    const PlyElement* vertex = nullptr;
    for (const auto& e : elements_)
      if (e.name == "vertex") vertex = &e;
    if (vertex == nullptr) fail("has no vertex element");
    for (const auto& e : elements_)
      if (e.name == "tristrips" && e.count > 0)
        fail("has triangle strips (element 'tristrips'), which are not read correctly here: store the triangles as "
             "'face' lists");
    nverts_ = vertex->count;
    for (const auto& e : elements_) {
      if (e.name == "vertex")
        for (const char* c : {"x", "y", "z"})
          if (std::none_of(e.props.begin(), e.props.end(), [&](const PlyProperty& p) { return p.name == c && !p.list; }))
            fail(std::string("vertex element has no scalar property '") + c + "'");
      if (e.props.empty() && !ascii_) continue;  // rows of no bytes
      for (std::uint64_t r = 0; r < e.count; ++r) {
        if (ascii_) begin_line(e, r);
        for (const auto& p : e.props) {
          if (!p.list) {
            const double v = value(e, r, p.size, p.is_float, p.is_signed);
            if (e.name == "vertex" && (p.name == "x" || p.name == "y" || p.name == "z") && !std::isfinite(v))
              fail("vertex " + std::to_string(r) + " has a non-finite " + p.name);
            continue;
          }
          const double n = value(e, r, p.count_size, false, p.count_signed);
          const bool face = e.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index");

          if (!(n >= 0) || n > static_cast<double>(kMaxPolygon) || (face && n < 3))
            fail(e.name + " " + std::to_string(r) + " lists " + io_num(n) + " items (" + (face ? "3" : "0") + ".." +
                 std::to_string(kMaxPolygon) + " allowed)");
          for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) {
            const double idx = value(e, r, p.size, p.is_float, p.is_signed);
            if (face && !(idx >= 0 && idx < static_cast<double>(nverts_) && idx == std::floor(idx)))
              fail("face " + std::to_string(r) + " names vertex " + io_num(idx) + " of " + std::to_string(nverts_));
          }
        }
        if (ascii_) end_line(e, r);
      }
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(file_.string() + ": PLY " + what);
  }
  static std::string io_num(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }

  bool next_header_line(std::string& line) {
    if (pos_ >= data_.size()) return false;
    const std::size_t nl = data_.find('\n', pos_);
    if (nl == std::string::npos) return false;  // the header ends with a newline
    line = data_.substr(pos_, nl - pos_);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos_ = nl + 1;
    return true;
  }

  void read_header() {
    std::string line;
    if (!next_header_line(line) || line != "ply") fail("file does not start with 'ply'");
    bool have_format = false, ended = false;
    while (next_header_line(line)) {
      std::istringstream ls(line);
      std::string w;
      ls >> w;
      if (w.empty() || w == "comment" || w == "obj_info") continue;
      if (w == "end_header") {
        ended = true;
        break;
      }
      // One format line and no words past what a line holds: the mesh library reads the
      // header by words and its first format, so a header this walk reads otherwise (a
      // second format line, a binary file walked as text) would let it allocate by
      // values this walk never checked (a list count of 5e8 from ASCII digits, 6.2 GB).
      std::string extra;
      if (w == "format") {
        std::string f, ver;
        ls >> f >> ver;
        if (have_format) fail("header has a second format line '" + line + "'");
        if (ver != "1.0" || (ls >> extra)) fail("format line '" + line + "' is not 'format <type> 1.0'");
        if (f == "ascii") ascii_ = true;
        else if (f == "binary_little_endian") big_ = false;
        else if (f == "binary_big_endian") big_ = true;
        else fail("format '" + f + "' is not ascii, binary_little_endian or binary_big_endian");
        have_format = true;
      } else if (w == "element") {
        PlyElement e;
        std::string count;
        ls >> e.name >> count;
        char* end = nullptr;
        const unsigned long long n = std::strtoull(count.c_str(), &end, 10);
        if (e.name.empty() || count.empty() || *end != '\0' || count[0] == '-' || n > kMaxElements)
          fail("element line '" + line + "' has no count in 0.." + std::to_string(kMaxElements));
        if (ls >> extra) fail("element line '" + line + "' has words after its count");
        e.count = n;
        elements_.push_back(e);
      } else if (w == "property") {
        if (elements_.empty()) fail("property before any element");
        PlyProperty p;
        std::string t;
        ls >> t;
        if (t == "list") {
          std::string ct, it;
          ls >> ct >> it >> p.name;
          bool cf = false;
          if (!ply_type(ct, p.count_size, cf, p.count_signed) || cf || !ply_type(it, p.size, p.is_float, p.is_signed))
            fail("property line '" + line + "' has an unknown or non-integer list type");
          p.list = true;
        } else {
          ls >> p.name;
          if (!ply_type(t, p.size, p.is_float, p.is_signed)) fail("property type '" + t + "' is unknown");
        }
        if (p.name.empty()) fail("property line '" + line + "' has no name");
        if (ls >> extra) fail("property line '" + line + "' has words after its name");
        elements_.back().props.push_back(p);
      } else {
        fail("header line '" + line + "' is not understood");
      }
    }
    if (!ended) fail("header has no end_header line");
    if (!have_format) fail("header has no format line");
  }

  // ASCII rows: one line per row (blank lines between are tolerated by no reader: refused).
  void begin_line(const PlyElement& e, std::uint64_t r) {
    if (pos_ >= data_.size())
      fail("file ends at " + e.name + " " + std::to_string(r) + " of " + std::to_string(e.count));
    const std::size_t nl = data_.find('\n', pos_);
    line_end_ = nl == std::string::npos ? data_.size() : nl;
  }
  void end_line(const PlyElement& e, std::uint64_t r) {
    while (pos_ < line_end_ && (data_[pos_] == ' ' || data_[pos_] == '\t' || data_[pos_] == '\r')) ++pos_;
    if (pos_ != line_end_) fail(e.name + " " + std::to_string(r) + " has more values than its properties");
    pos_ = line_end_ + 1;
  }

  double value(const PlyElement& e, std::uint64_t r, int size, bool is_float, bool is_signed) {
    if (ascii_) {
      while (pos_ < line_end_ && (data_[pos_] == ' ' || data_[pos_] == '\t')) ++pos_;
      const std::size_t start = pos_;
      while (pos_ < line_end_ && data_[pos_] != ' ' && data_[pos_] != '\t' && data_[pos_] != '\r') ++pos_;
      if (start == pos_) fail(e.name + " " + std::to_string(r) + " has fewer values than its properties");
      const std::string tok = data_.substr(start, pos_ - start);
      // A NUL byte would end the number for strtod unseen (and the mesh library leaks
      // memory on such rows): refused as such.
      if (tok.find('\0') != std::string::npos) fail(e.name + " " + std::to_string(r) + " has a NUL byte in an ASCII file");
      char* end = nullptr;
      const double v = std::strtod(tok.c_str(), &end);
      if (end != tok.c_str() + tok.size())
        fail(e.name + " " + std::to_string(r) + " has a value '" + tok + "' that is not a number");
      if (!is_float && v != std::floor(v)) fail(e.name + " " + std::to_string(r) + " has a non-integer '" + tok + "'");
      return v;
    }
    if (data_.size() - pos_ < static_cast<std::size_t>(size))
      fail("file ends inside " + e.name + " " + std::to_string(r) + " of " + std::to_string(e.count) + " (" +
           std::to_string(data_.size()) + " bytes)");
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, static_cast<std::size_t>(size));
    pos_ += static_cast<std::size_t>(size);
    const bool host_big = std::endian::native == std::endian::big;
    if (big_ != host_big) std::reverse(b, b + size);
    if (is_float) {
      if (size == 4) {
        float f;
        std::memcpy(&f, b, 4);
        return f;
      }
      double d;
      std::memcpy(&d, b, 8);
      return d;
    }
    std::uint64_t u = 0;
    std::memcpy(&u, b, static_cast<std::size_t>(size));  // little-endian host order assumed below
    if (host_big) u >>= 8 * (8 - size);
    if (is_signed && size < 8 && (u >> (8 * size - 1)) & 1u) return static_cast<double>(u) - std::ldexp(1.0, 8 * size);
    return static_cast<double>(u);
  }

  std::filesystem::path file_;
  std::string data_;
  std::size_t pos_ = 0, line_end_ = 0;
  bool ascii_ = false, big_ = false;
  std::vector<PlyElement> elements_;
  std::uint64_t nverts_ = 0;
};

Mesh load_ply(const std::filesystem::path& file) {
  PlyCheck(file).run();  // before the mesh library sees the file
  Assimp::Importer imp;
  // Read without post-processing first: no vertex joining or other changes (the file's
  // vertices are the mesh's vertices), and nothing runs on faces not yet checked.
  const aiScene* sc = imp.ReadFile(file.string(), 0);
  const auto unreadable = [&](std::string msg) {
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    return InputError(file.string() + ": not a readable PLY mesh (" + msg + ")");
  };
  if (sc == nullptr) throw unreadable(imp.GetErrorString());
  if (sc->mNumMeshes == 0) throw unreadable("no mesh in file");
  // The triangulation step trusts each mesh's primitive-type flags and aborts the process
  // when they claim polygons that are not there (e.g. the degenerate faces a triangle strip
  // with restarts leaves). Check every index, then set the flags from the faces themselves.
  bool polygons = false;
  for (unsigned k = 0; k < sc->mNumMeshes; ++k) {
    aiMesh* am = sc->mMeshes[k];
    unsigned types = 0;
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      for (unsigned j = 0; j < face.mNumIndices; ++j)
        if (face.mIndices[j] >= am->mNumVertices)
          throw InputError(file.string() + ": face " + std::to_string(f) + " names vertex " +
                           std::to_string(face.mIndices[j]) + " of " + std::to_string(am->mNumVertices));
      switch (face.mNumIndices) {
        case 0: break;
        case 1: types |= aiPrimitiveType_POINT; break;
        case 2: types |= aiPrimitiveType_LINE; break;
        case 3: types |= aiPrimitiveType_TRIANGLE; break;
        default: types |= aiPrimitiveType_POLYGON; polygons = true;
      }
    }
    // A mesh without faces of any kind gets a non-polygon flag, so that the step leaves it alone.
    am->mPrimitiveTypes = types != 0 ? types : static_cast<unsigned>(aiPrimitiveType_POINT);
  }
  if (polygons) {
    sc = imp.ApplyPostProcessing(aiProcess_Triangulate);
    if (sc == nullptr) throw unreadable(imp.GetErrorString());
  }
  Mesh m;
  m.name = file.string();
  bool have_colour = false;
  for (unsigned k = 0; k < sc->mNumMeshes; ++k) {
    const aiMesh* am = sc->mMeshes[k];
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (unsigned i = 0; i < am->mNumVertices; ++i) {
      m.positions.emplace_back(am->mVertices[i].x, am->mVertices[i].y, am->mVertices[i].z);
      if (am->HasVertexColors(0)) {
        const aiColor4D& c = am->mColors[0][i];
        m.albedo.push_back(std::clamp((c.r + c.g + c.b) / 3.0, 0.0, 1.0));
        have_colour = true;
      } else {
        m.albedo.push_back(-1.0);
      }
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no surface
      std::array<std::uint32_t, 3> t{};
      for (int j = 0; j < 3; ++j) {
        if (face.mIndices[j] >= am->mNumVertices)
          throw InputError(m.name + ": face " + std::to_string(f) + " names vertex " + std::to_string(face.mIndices[j]) +
                           " of " + std::to_string(am->mNumVertices));
        t[j] = base + face.mIndices[j];
      }
      m.triangles.push_back(t);
    }
  }
  if (!have_colour) {
    m.albedo.clear();
  } else {
    for (double& a : m.albedo)
      if (a < 0) a = 0.8;
  }
  return m;
}

// Adds a (u, v) grid surface: pos(u, v) for u in [0,1] (nu steps), v in [0,1] (nv steps),
// wrapping in u and/or v (shared seam vertices), with optional collapsed poles handled by
// the caller (pole vertices are merged by `key`).
struct Builder {
  Mesh m;
  std::uint32_t add(const glm::dvec3& p, double albedo) {
    m.positions.push_back(p);
    m.albedo.push_back(albedo);
    return static_cast<std::uint32_t>(m.positions.size() - 1);
  }
  void tri(std::uint32_t a, std::uint32_t b, std::uint32_t c) { m.triangles.push_back({a, b, c}); }
  void quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {  // counter-clockwise a b c d
    tri(a, b, c);
    tri(a, c, d);
  }
  // Rectangle: origin o, edges eu, ev (normal = eu x ev), n x n quads.
  void grid(const glm::dvec3& o, const glm::dvec3& eu, const glm::dvec3& ev, int nu, int nvv, double albedo) {
    std::vector<std::uint32_t> id;
    for (int j = 0; j <= nvv; ++j)
      for (int i = 0; i <= nu; ++i) id.push_back(add(o + eu * (double(i) / nu) + ev * (double(j) / nvv), albedo));
    for (int j = 0; j < nvv; ++j)
      for (int i = 0; i < nu; ++i) {
        const auto a = id[j * (nu + 1) + i];
        quad(a, a + 1, a + 1 + (nu + 1), a + (nu + 1));
      }
  }
  // UV sphere with single pole vertices (closed 2-manifold).
  void sphere(const glm::dvec3& c, double r, int nlat, int nlon, double albedo) {
    const auto north = add(c + glm::dvec3(0, 0, r), albedo);
    std::vector<std::uint32_t> id;
    for (int i = 1; i < nlat; ++i) {
      const double t = kPi * i / nlat;
      for (int j = 0; j < nlon; ++j) {
        const double p = 2 * kPi * j / nlon;
        id.push_back(add(c + r * glm::dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)), albedo));
      }
    }
    const auto south = add(c - glm::dvec3(0, 0, r), albedo);
    auto at = [&](int i, int j) { return id[(i - 1) * nlon + (j % nlon)]; };
    for (int j = 0; j < nlon; ++j) tri(north, at(1, j), at(1, j + 1));
    for (int i = 1; i < nlat - 1; ++i)
      for (int j = 0; j < nlon; ++j) quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
    for (int j = 0; j < nlon; ++j) tri(south, at(nlat - 1, j + 1), at(nlat - 1, j));
  }
};
}  // namespace

std::vector<std::string> builtin_scene_names() { return {"sphere-on-plane", "box-occluder", "torus", "sphere"}; }

Mesh builtin_scene(const std::string& name, int res) {
  if (res < 4 || res > 4096) throw InputError("builtin scene resolution must be in 4..4096, got " + std::to_string(res));
  Builder b;
  if (name == "sphere-on-plane") {
    b.grid({-2, -2, 0}, {4, 0, 0}, {0, 4, 0}, res, res, 0.8);
    b.sphere({0, 0, 0.5}, 0.5, res, 2 * res, 0.8);
  } else if (name == "box-occluder") {
    b.grid({-2, -2, 0}, {4, 0, 0}, {0, 4, 0}, res, res, 0.8);
    const int n = std::max(2, res / 4);
    // Four single-sheet walls of a 1 x 1 x 1 box (normals outwards) and a roof square.
    b.grid({-0.5, -0.5, 0}, {1, 0, 0}, {0, 0, 1}, n, n, 0.6);   // -y wall, normal -y
    b.grid({0.5, 0.5, 0}, {-1, 0, 0}, {0, 0, 1}, n, n, 0.6);    // +y wall, normal +y
    b.grid({0.5, -0.5, 0}, {0, 1, 0}, {0, 0, 1}, n, n, 0.6);    // +x wall
    b.grid({-0.5, 0.5, 0}, {0, -1, 0}, {0, 0, 1}, n, n, 0.6);   // -x wall
    b.grid({-0.8, -0.8, 1.4}, {0, 1.6, 0}, {1.6, 0, 0}, n, n, 0.6);   // occluder: a thin plate, lower face down
    b.grid({-0.8, -0.8, 1.42}, {1.6, 0, 0}, {0, 1.6, 0}, n, n, 0.6);  // and upper face up
  } else if (name == "torus") {
    const double R = 1.0, r = 0.35;
    const int nu = 2 * res, nv = res;
    std::vector<std::uint32_t> id;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
        id.push_back(b.add({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)}, 0.8));
      }
    auto at = [&](int i, int j) { return id[(i % nu) * nv + (j % nv)]; };
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) b.quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
  } else if (name == "sphere") {
    b.sphere({0, 0, 0}, 1.0, res, 2 * res, 0.8);
  } else {
    std::string names;
    for (const auto& n : builtin_scene_names()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("unknown built-in scene '" + name + "' (" + names + ")");
  }
  b.m.name = "builtin:" + name;
  compute_normals(b.m);
  validate(b.m);
  return std::move(b.m);
}

void validate(const Mesh& m) {
  if (m.positions.empty() || m.triangles.empty())
    throw InputError(m.name + ": empty mesh (" + std::to_string(m.positions.size()) + " vertices, " +
                     std::to_string(m.triangles.size()) + " triangles)");
  if (m.positions.size() > 0xffffffffu) throw InputError(m.name + ": too many vertices");
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const auto& p = m.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError(m.name + ": vertex " + std::to_string(i) + " is not finite (" + std::to_string(p.x) + ", " +
                       std::to_string(p.y) + ", " + std::to_string(p.z) + ")");
  }
  if (!m.albedo.empty() && m.albedo.size() != m.positions.size())
    throw InputError(m.name + ": " + std::to_string(m.albedo.size()) + " albedos for " + std::to_string(m.positions.size()) + " vertices");
  for (std::size_t i = 0; i < m.albedo.size(); ++i)
    if (!(m.albedo[i] >= 0 && m.albedo[i] <= 1))
      throw InputError(m.name + ": albedo of vertex " + std::to_string(i) + " is " + std::to_string(m.albedo[i]) + " (not in [0, 1])");
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const auto& t = m.triangles[f];
    for (auto v : t)
      if (v >= m.positions.size())
        throw InputError(m.name + ": triangle " + std::to_string(f) + " names vertex " + std::to_string(v) + " of " +
                         std::to_string(m.positions.size()));
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      throw InputError(m.name + ": triangle " + std::to_string(f) + " repeats a vertex (" + std::to_string(t[0]) + ", " +
                       std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")");
    for (int k = 0; k < 3; ++k) {
      auto a = t[k], c = t[(k + 1) % 3];
      if (a > c) std::swap(a, c);
      if (++edges[{a, c}] == 3)
        throw InputError(m.name + ": non-manifold edge (" + std::to_string(a) + ", " + std::to_string(c) +
                         ") is shared by more than two triangles");
    }
  }
}

void compute_normals(Mesh& m) {
  m.normals.assign(m.positions.size(), glm::dvec3(0.0));
  for (const auto& t : m.triangles) {
    const glm::dvec3 n = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
    if (!std::isfinite(n.x + n.y + n.z)) continue;
    for (auto v : t) m.normals[v] += n;  // |n| = twice the area: area weighting
  }
  for (auto& n : m.normals) {
    const double l = glm::length(n);
    n = (l > 0 && std::isfinite(l)) ? n / l : glm::dvec3(0, 0, 1);
  }
}

double bounding_diagonal(const Mesh& m) {
  if (m.positions.empty()) return 0;
  glm::dvec3 lo = m.positions[0], hi = lo;
  for (const auto& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

Mesh load_mesh(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw InputError(file.string() + ": no such mesh file");
  const std::string ext = lower_ext(file);
  Mesh m;
  if (ext == ".obj")
    m = load_obj(file);
  else if (ext == ".ply")
    m = load_ply(file);
  else
    throw InputError(file.string() + ": unknown mesh format '" + ext + "' (.obj, .ply)");
  validate(m);
  compute_normals(m);
  return m;
}

}  // namespace atmosh::prt
