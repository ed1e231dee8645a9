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

#include <filesystem>
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

ExrImage read_exr(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) throw InputError("cannot read EXR file '" + file.string() + "'");
  try {
    Imf::InputFile in(file.c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    ExrImage img;
    img.width = dw.max.x - dw.min.x + 1;
    img.height = dw.max.y - dw.min.y + 1;
    Imf::FrameBuffer fb;
    for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it)
      img.channels.emplace_back(it.name());
    img.data.assign(img.channels.size(), std::vector<float>(static_cast<std::size_t>(img.width) * img.height));
    for (std::size_t c = 0; c < img.channels.size(); ++c) {
      char* base = reinterpret_cast<char*>(img.data[c].data()) -
                   (static_cast<std::ptrdiff_t>(dw.min.x) + static_cast<std::ptrdiff_t>(dw.min.y) * img.width) *
                       static_cast<std::ptrdiff_t>(sizeof(float));
      fb.insert(img.channels[c], Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * img.width));
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
