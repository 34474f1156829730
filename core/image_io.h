// Image and text output. Every write goes to a temporary file in the same folder,
// is flushed and synced, then renamed over the target: a failed or interrupted write
// leaves any existing file untouched and no temporary file behind.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "film.h"

namespace rt {

enum class ImageFormat { Unknown, Ppm, Png };
ImageFormat format_from_path(const std::string& path);

// 8-bit RGB bytes of an image, with the original's rounding.
std::vector<std::uint8_t> to_rgb8(const Image& img);

// Returns an empty string on success, else a message saying why.
std::string write_image(const std::string& path, const Image& img);
std::string write_rgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);
std::string write_rgb8(const std::string& path, int width, int height, const std::uint8_t* rgb, std::size_t size);
std::string write_file_atomic(const std::string& path, const std::string& data);
// The same for data in several pieces, written one after the other.
std::string write_file_atomic(const std::string& path, std::initializer_list<std::string_view> parts);
// Reads a whole file; empty message on success. Refuses files over max_bytes.
std::string read_file(const std::string& path, std::string& out, std::size_t max_bytes);

// Reads a binary (P6) or ASCII (P3) PPM; empty message on success.
std::string read_ppm(const std::string& path, int& width, int& height, std::vector<std::uint8_t>& rgb);

}  // namespace rt
