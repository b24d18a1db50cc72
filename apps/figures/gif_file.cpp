// Animated GIF files (see gif_file.hpp).
#include "gif_file.hpp"

#include <fcntl.h>
#include <gif_lib.h>
#include <unistd.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <suffuse/error.hpp>
#include <unordered_map>

#include "colour_map.hpp"

namespace suffuse::plot {

namespace {

std::string gif_error(int code) {
  const char* text = GifErrorString(code);
  return text ? text : "giflib error " + std::to_string(code);
}

// The index of the palette colour nearest each RGB colour met so far.
class Quantiser {
 public:
  explicit Quantiser(const std::vector<std::array<std::uint8_t, 3>>& palette) : palette_(palette) {}
  GifByteType index(const unsigned char* rgb) {
    const std::uint32_t key = (std::uint32_t{rgb[0]} << 16) | (std::uint32_t{rgb[1]} << 8) | rgb[2];
    const auto found = cache_.find(key);
    if (found != cache_.end()) return found->second;
    int best = 0, best_distance = 1 << 30;
    for (std::size_t k = 0; k < palette_.size(); ++k) {
      int d = 0;
      for (int c = 0; c < 3; ++c) d += (rgb[c] - palette_[k][c]) * (rgb[c] - palette_[k][c]);
      if (d < best_distance) best_distance = d, best = static_cast<int>(k);
    }
    return cache_[key] = static_cast<GifByteType>(best);
  }

 private:
  const std::vector<std::array<std::uint8_t, 3>>& palette_;
  std::unordered_map<std::uint32_t, GifByteType> cache_;
};

// Frees a GIF that EGifSpew has not taken over.
struct GifCloser {
  void operator()(GifFileType* gif) const {
    int error = 0;
    if (gif) EGifCloseFile(gif, &error);
  }
};

}  // namespace

std::vector<std::array<std::uint8_t, 3>> gif_palette() {
  std::vector<std::array<std::uint8_t, 3>> palette;
  constexpr int colours = 216, greys = 40;
  for (int k = 0; k < colours; ++k) {
    const auto c = viridis(static_cast<double>(k) / (colours - 1));
    palette.push_back({static_cast<std::uint8_t>(std::lround(255 * c[0])),
                       static_cast<std::uint8_t>(std::lround(255 * c[1])),
                       static_cast<std::uint8_t>(std::lround(255 * c[2]))});
  }
  for (int k = 0; k < greys; ++k) {
    const auto g = static_cast<std::uint8_t>(std::lround(255.0 * k / (greys - 1)));
    palette.push_back({g, g, g});
  }
  return palette;
}

void write_gif(const std::filesystem::path& file, const std::vector<vtkSmartPointer<vtkImageData>>& frames, int delay) {
  if (frames.empty()) throw Error("cannot write " + file.string() + ": no frames");
  int dims[3];
  frames.front()->GetDimensions(dims);
  const int width = dims[0], height = dims[1];
  const auto palette = gif_palette();
  Quantiser quantiser(palette);

  // Opened here rather than by giflib, which would make the file readable by its owner only.
  const int fd = open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (fd < 0) throw Error("cannot write " + file.string() + ": " + std::strerror(errno));
  int error = 0;
  std::unique_ptr<GifFileType, GifCloser> gif(EGifOpenFileHandle(fd, &error));
  if (!gif) {
    close(fd);
    throw Error("cannot write " + file.string() + ": " + gif_error(error));
  }
  gif->SWidth = width;
  gif->SHeight = height;
  gif->SColorResolution = 8;
  gif->SBackGroundColor = static_cast<int>(palette.size()) - 1;  // white
  std::vector<GifColorType> colours;
  for (const auto& c : palette) colours.push_back({c[0], c[1], c[2]});
  gif->SColorMap = GifMakeMapObject(static_cast<int>(colours.size()), colours.data());
  if (!gif->SColorMap) throw Error("cannot write " + file.string() + ": out of memory");

  for (std::size_t f = 0; f < frames.size(); ++f) {
    vtkImageData* image = frames[f];
    image->GetDimensions(dims);
    vtkDataArray* pixels = image->GetPointData()->GetScalars();
    auto* rgb = vtkUnsignedCharArray::SafeDownCast(pixels);
    if (dims[0] != width || dims[1] != height || !rgb || rgb->GetNumberOfComponents() < 3)
      throw Error("cannot write " + file.string() + ": frame " + std::to_string(f) + " is not a " +
                  std::to_string(width) + " x " + std::to_string(height) + " RGB image");
    SavedImage* saved = GifMakeSavedImage(gif.get(), nullptr);
    if (!saved) throw Error("cannot write " + file.string() + ": out of memory");
    saved->ImageDesc.Left = saved->ImageDesc.Top = 0;
    saved->ImageDesc.Width = width;
    saved->ImageDesc.Height = height;
    saved->ImageDesc.Interlace = false;
    saved->ImageDesc.ColorMap = nullptr;
    saved->RasterBits = static_cast<GifByteType*>(std::malloc(static_cast<std::size_t>(width) * height));
    if (!saved->RasterBits) throw Error("cannot write " + file.string() + ": out of memory");
    const int components = rgb->GetNumberOfComponents();
    const unsigned char* data = rgb->GetPointer(0);
    for (int row = 0; row < height; ++row)  // GIF rows run from the top
      for (int col = 0; col < width; ++col)
        saved->RasterBits[static_cast<std::size_t>(row) * width + col] =
            quantiser.index(data + (static_cast<std::size_t>(height - 1 - row) * width + col) * components);
    if (f == 0) {
      // Loop for ever (the Netscape application extension).
      static const char netscape[] = "NETSCAPE2.0";
      static const unsigned char loop[] = {1, 0, 0};
      if (GifAddExtensionBlock(&saved->ExtensionBlockCount, &saved->ExtensionBlocks, APPLICATION_EXT_FUNC_CODE, 11,
                               reinterpret_cast<unsigned char*>(const_cast<char*>(netscape))) == GIF_ERROR ||
          GifAddExtensionBlock(&saved->ExtensionBlockCount, &saved->ExtensionBlocks, CONTINUE_EXT_FUNC_CODE, 3,
                               const_cast<unsigned char*>(loop)) == GIF_ERROR)
        throw Error("cannot write " + file.string() + ": out of memory");
    }
    GraphicsControlBlock control{DISPOSAL_UNSPECIFIED, false, delay, NO_TRANSPARENT_COLOR};
    if (EGifGCBToSavedExtension(&control, gif.get(), static_cast<int>(f)) == GIF_ERROR)
      throw Error("cannot write " + file.string() + ": out of memory");
  }
  // EGifSpew writes and closes the GIF and frees its struct, but not the
  // images and colour map made for it (giflib 5.2): those are freed here,
  // from pointers taken before it (found by LeakSanitizer).
  SavedImage* images = gif->SavedImages;
  const int image_count = gif->ImageCount;
  ColorMapObject* colour_map = gif->SColorMap;
  const int status = EGifSpew(gif.release());
  for (int i = 0; i < image_count; ++i) {
    std::free(images[i].RasterBits);
    GifFreeExtensions(&images[i].ExtensionBlockCount, &images[i].ExtensionBlocks);
  }
  std::free(images);
  GifFreeMapObject(colour_map);
  if (status == GIF_ERROR) throw Error("cannot write " + file.string() + ": giflib could not write it");
}

}  // namespace suffuse::plot
