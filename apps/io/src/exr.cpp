#include "atmosh/io/exr.hpp"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <ImfFloatAttribute.h>
#include <Iex.h>

#include <cstdint>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <stdexcept>

#include "atmosh/error.hpp"
#include "atmosh/io/atomic.hpp"

namespace atmosh::io {

ExrImage::ExrImage(int w, int h, std::vector<std::string> channel_names)
    : width(w), height(h), channels(std::move(channel_names)) {
  if (w <= 0 || h <= 0) throw std::invalid_argument("ExrImage: size must be positive");
  data.assign(channels.size(), std::vector<float>(static_cast<std::size_t>(w) * h, 0.0f));
}

int ExrImage::find_channel(const std::string& name) const {
  for (std::size_t i = 0; i < channels.size(); ++i)
    if (channels[i] == name) return static_cast<int>(i);
  return -1;
}

std::vector<float>& ExrImage::channel(const std::string& name) {
  const int i = find_channel(name);
  if (i < 0) throw std::out_of_range("EXR image has no channel '" + name + "'");
  return data[static_cast<std::size_t>(i)];
}

const std::vector<float>& ExrImage::channel(const std::string& name) const {
  return const_cast<ExrImage*>(this)->channel(name);
}

void write_exr(const std::filesystem::path& file, const ExrImage& image, const Provenance& provenance) {
  if (image.data.size() != image.channels.size()) throw std::invalid_argument("ExrImage: channel count mismatch");
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  for (const auto& c : image.data)
    if (c.size() != n) throw std::invalid_argument("ExrImage: channel size mismatch");
  write_atomically(file, [&](const std::filesystem::path& tmp) {
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    for (const auto& name : image.channels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    for (const auto& [k, v] : provenance.entries) header.insert("atmosh:" + k, Imf::StringAttribute(v));
    for (const auto& [k, v] : image.string_attributes) header.insert(k, Imf::StringAttribute(v));
    for (const auto& [k, v] : image.float_attributes) header.insert(k, Imf::FloatAttribute(v));
    Imf::FrameBuffer fb;
    for (std::size_t c = 0; c < image.channels.size(); ++c) {
      char* base = reinterpret_cast<char*>(const_cast<float*>(image.data[c].data()));
      fb.insert(image.channels[c], Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * image.width));
    }
    try {
      Imf::OutputFile out(tmp.c_str(), header);
      out.setFrameBuffer(fb);
      out.writePixels(image.height);
    } catch (const std::exception& e) {
      throw std::runtime_error("writing EXR " + file.string() + ": " + e.what());
    }
  });
}

std::size_t exr_image_bytes(std::int64_t width, std::int64_t height, std::size_t channels) {
  if (width <= 0 || height <= 0) return 0;
  return static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * channels * sizeof(float);
}

namespace {
// OpenEXR allocates by the header's word before checking it against the file (a
// string attribute declaring 1.9 GB is allocated whole; the offset table follows the
// data window's height): the header is walked here first. Single-part flat images
// only; every attribute must lie inside the file; the data window and the tile count
// are bounded. OpenEXR reads the value of a type it knows by the type's own layout, not
// by the declared length (a channel list until its empty name, a box2i as 16 bytes): a
// value whose layout does not fill its length exactly would make OpenEXR read the rest
// of the header from another place than this walk (a string of 1.9 GB again, out of
// memory under the fuzzer), so every known type's value must have its layout exactly.

// The value sizes of OpenEXR 3.1's fixed-size attribute types (ImfStandardAttributes);
// 0: the type has no fixed size.
std::size_t exr_fixed_size(const std::string& type) {
  static const std::pair<const char*, std::size_t> sizes[] = {
      {"box2i", 16}, {"box2f", 16},  {"chromaticities", 32}, {"compression", 1}, {"double", 8},
      {"envmap", 1}, {"float", 4},   {"int", 4},             {"keycode", 28},    {"lineOrder", 1},
      {"m33f", 36},  {"m33d", 72},   {"m44f", 64},           {"m44d", 128},      {"rational", 8},
      {"tiledesc", 9}, {"timecode", 8}, {"v2i", 8},          {"v2f", 8},         {"v2d", 16},
      {"v3i", 12},   {"v3f", 12},    {"v3d", 24},            {"deepImageState", 1}};
  for (const auto& [name, n] : sizes)
    if (type == name) return n;
  return 0;
}

// Why the value v (n bytes) of a variable-layout type does not fill n exactly; "" when
// it does or when OpenEXR reads the type by its length.
std::string exr_layout_fault(const std::string& type, const unsigned char* v, std::size_t n) {
  auto i32 = [&](std::size_t at) {
    return static_cast<std::int32_t>(std::uint32_t{v[at]} | std::uint32_t{v[at + 1]} << 8 |
                                     std::uint32_t{v[at + 2]} << 16 | std::uint32_t{v[at + 3]} << 24);
  };
  if (type == "chlist") {  // {name NUL, 16 bytes}* NUL
    std::size_t at = 0;
    for (;;) {
      std::size_t end = at;
      while (end < n && v[end] != 0) ++end;
      if (end >= n) return "a channel list without its end";
      if (end - at > 255) return "a channel name longer than 255 bytes";
      if (end == at) return end + 1 == n ? "" : "bytes after the channel list's end";
      at = end + 1 + 16;
      if (at > n) return "a channel record cut short";
    }
  }
  if (type == "stringvector") {  // {int32 length, chars}*, read while inside n
    for (std::size_t at = 0; at < n;) {
      if (at + 4 > n) return "a string length cut short";
      const std::int32_t len = i32(at);
      if (len < 0 || at + 4 + static_cast<std::size_t>(len) > n) return "a string longer than the attribute";
      at += 4 + static_cast<std::size_t>(len);
    }
    return "";
  }
  if (type == "preview") {  // uint32 width, height, 4 bytes per pixel
    if (n < 8) return "a preview without its size";
    const std::uint64_t w = static_cast<std::uint32_t>(i32(0)), h = static_cast<std::uint32_t>(i32(4));
    return 8 + 4 * w * h == n ? "" : "a preview of another size than its bytes";
  }
  if (type == "floatvector") return n % 4 == 0 ? "" : "a float vector of a partial float";
  return "";
}

void check_exr_header(const std::filesystem::path& file) {
  auto bad = [&](const std::string& why) { return InputError("cannot read EXR file '" + file.string() + "': " + why); };
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(file, ec);
  std::ifstream in(file, std::ios::binary);
  auto u32 = [&](const unsigned char* b) {
    return std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8 | std::uint32_t{b[2]} << 16 | std::uint32_t{b[3]} << 24;
  };
  unsigned char head[8];
  if (ec || !in.read(reinterpret_cast<char*>(head), 8)) throw bad("shorter than an EXR header");
  if (u32(head) != 20000630u) throw bad("no EXR magic number");
  const std::uint32_t version = u32(head + 4);
  if (version & 0x1800u) throw bad("multi-part or deep images are not supported");
  const std::size_t max_name = (version & 0x400u) ? 255 : 31;
  auto cstr = [&](const char* what) {
    std::string s;
    for (char c; in.get(c) && c != '\0';) {
      s += c;
      if (s.size() > max_name) throw bad(std::string(what) + " longer than " + std::to_string(max_name) + " bytes");
    }
    if (!in) throw bad("header ends inside an attribute");
    return s;
  };
  std::int64_t w = 0, h = 0;
  for (int count = 0;; ++count) {
    if (count > 4096) throw bad("more than 4096 header attributes");
    const std::string name = cstr("attribute name");
    if (name.empty()) break;  // end of the header
    const std::string type = cstr("attribute type");
    unsigned char lb[4];
    if (!in.read(reinterpret_cast<char*>(lb), 4)) throw bad("header ends inside attribute '" + name + "'");
    const auto len = static_cast<std::int32_t>(u32(lb));
    const std::uint64_t at = static_cast<std::uint64_t>(in.tellg());
    if (len < 0 || at + static_cast<std::uint64_t>(len) > size)
      throw bad("attribute '" + name + "' declares " + std::to_string(len) + " bytes, more than the file holds");
    const std::size_t fixed = exr_fixed_size(type);
    if (fixed != 0 && static_cast<std::size_t>(len) != fixed)
      throw bad("attribute '" + name + "' of type " + type + " holds " + std::to_string(len) + " bytes, not " +
                std::to_string(fixed));
    const bool layout = type == "chlist" || type == "stringvector" || type == "preview" || type == "floatvector";
    std::string value(layout ? static_cast<std::size_t>(len) : static_cast<std::size_t>(std::min<std::int32_t>(len, 64)),
                      '\0');
    if (!in.read(value.data(), static_cast<std::streamsize>(value.size())))
      throw bad("header ends inside attribute '" + name + "'");
    in.seekg(static_cast<std::streamoff>(at) + len);
    const auto* v = reinterpret_cast<const unsigned char*>(value.data());
    if (layout) {
      const std::string fault = exr_layout_fault(type, v, value.size());
      if (!fault.empty()) throw bad("attribute '" + name + "' of type " + type + " holds " + fault);
    }
    if (name == "dataWindow" && type == "box2i" && len == 16) {
      w = std::int64_t{static_cast<std::int32_t>(u32(v + 8))} - static_cast<std::int32_t>(u32(v)) + 1;
      h = std::int64_t{static_cast<std::int32_t>(u32(v + 12))} - static_cast<std::int32_t>(u32(v + 4)) + 1;
      if (w < 1 || h < 1 || w > kMaxExrSide || h > kMaxExrSide)
        throw bad("data window " + std::to_string(w) + " x " + std::to_string(h) + " is not an image of 1.." +
                  std::to_string(kMaxExrSide) + " pixels a side");
    }
    if (name == "tiles" && type == "tiledesc" && len == 9) {
      const std::uint32_t tx = u32(v), ty = u32(v + 4);
      if (tx < 8 || ty < 8 || tx > 65536 || ty > 65536 || (v[8] & 0x0f) != 0)
        throw bad("tiles of " + std::to_string(tx) + " x " + std::to_string(ty) +
                  " (or with levels) are not supported (one level, 8..65536 a side)");
      if (w > 0 && ((w + tx - 1) / tx) * ((h + ty - 1) / ty) > (std::int64_t{1} << 20))
        throw bad("more than 2^20 tiles");
    }
  }
  if (w == 0) throw bad("no data window");
}
}  // namespace

ExrImage read_exr(const std::filesystem::path& file, std::size_t max_bytes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw InputError("cannot read EXR file '" + file.string() + "'");
  check_exr_header(file);
  try {
    Imf::InputFile in(file.c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    // The header is the file's word only: check it before allocating by it.
    const std::int64_t w = std::int64_t{dw.max.x} - dw.min.x + 1, h = std::int64_t{dw.max.y} - dw.min.y + 1;
    if (w < 1 || h < 1 || w > kMaxExrSide || h > kMaxExrSide)
      throw InputError(file.string() + ": EXR data window " + std::to_string(w) + " x " + std::to_string(h) +
                       " is not an image of 1.." + std::to_string(kMaxExrSide) + " pixels a side");
    std::size_t nch = 0;
    for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it) {
      if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
        throw InputError(file.string() + ": EXR channel '" + it.name() + "' is subsampled (not supported)");
      ++nch;
    }
    if (const std::size_t bytes = exr_image_bytes(w, h, nch); bytes > max_bytes)
      throw InputError(file.string() + ": EXR of " + std::to_string(w) + " x " + std::to_string(h) + " x " +
                       std::to_string(nch) + " channels needs " + std::to_string(bytes >> 20) +
                       " MiB as float32, more than the limit of " + std::to_string(max_bytes >> 20) + " MiB");
    ExrImage img;
    img.width = static_cast<int>(w);
    img.height = static_cast<int>(h);
    Imf::FrameBuffer fb;
    for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it)
      img.channels.emplace_back(it.name());
    img.data.assign(img.channels.size(), std::vector<float>(static_cast<std::size_t>(img.width) * img.height));
    for (std::size_t c = 0; c < img.channels.size(); ++c) {
      // Slice::Make offsets the origin by the data window (integer arithmetic, no pointer overflow).
      fb.insert(img.channels[c], Imf::Slice::Make(Imf::FLOAT, img.data[c].data(), dw, sizeof(float),
                                                  sizeof(float) * static_cast<std::size_t>(img.width)));
    }
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    for (auto it = in.header().begin(); it != in.header().end(); ++it) {
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        img.string_attributes[it.name()] = s->value();
      else if (const auto* f = dynamic_cast<const Imf::FloatAttribute*>(&it.attribute()))
        img.float_attributes[it.name()] = f->value();
    }
    return img;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    std::string msg = e.what();
    if (auto p = msg.find('\n'); p != std::string::npos) msg.resize(p);
    throw InputError("cannot read EXR file '" + file.string() + "': " + msg);
  }
}

}  // namespace atmosh::io
