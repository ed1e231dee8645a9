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
// are bounded.
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
    std::string value(static_cast<std::size_t>(std::min<std::int32_t>(len, 64)), '\0');
    in.read(value.data(), static_cast<std::streamsize>(value.size()));
    in.seekg(static_cast<std::streamoff>(at) + len);
    const auto* v = reinterpret_cast<const unsigned char*>(value.data());
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
