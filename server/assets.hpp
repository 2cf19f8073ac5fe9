// The web page, embedded at build time (embed_assets.cmake): the only files the server serves.
#pragma once
#include <string_view>
#include <vector>

namespace tp::server {

struct Asset {
  std::string_view path;  // "/index.html"
  std::string_view mime;
  std::string_view body;
};

const std::vector<Asset>& assets();

}  // namespace tp::server
