// split_path_list: colon-separated directory lists, empty entries dropped, order kept.
#include "common/path_list.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using List = std::vector<std::string>;

TEST_CASE("split_path_list splits at colons and drops empty entries") {
  CHECK(gm::split_path_list("") == List{});
  CHECK(gm::split_path_list(":::") == List{});
  CHECK(gm::split_path_list("a") == List{"a"});
  CHECK(gm::split_path_list("a::b:") == List{"a", "b"});
  CHECK(gm::split_path_list(":/x/y:rel/z") == List{"/x/y", "rel/z"});
}
