// The Siconos reader: dense LCP and relay files as written, told apart by their contents, and
// bad input named by file and line.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/io/siconos.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::dat_files;
using test::kSiconosDir;
namespace fs = std::filesystem;

namespace {

/// Writes text to a fresh temporary file and returns its path.
std::string temp_file(const std::string& name, const std::string& text) {
  static const fs::path dir = test::scratch_dir("lcp_text");
  const fs::path path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

}  // namespace

TEST_CASE("the Siconos reader reads dense files as written", "[siconos]") {
  const StoredLcp cps1 = read_siconos((kSiconosDir / "lcp" / "lcp_CPS_1.dat").string(), false);
  CHECK(cps1.M == MatX::Ones(2, 2));
  // The numbers are M column by column (siconos.hpp): CPS 2's second line is M's second column.
  const StoredLcp cps2 = read_siconos((kSiconosDir / "lcp" / "lcp_CPS_2.dat").string(), false);
  CHECK(cps2.M.col(1) == (VecX(3) << -1, 0, 1).finished());
  CHECK(cps2.q == (VecX(3) << -3, 6, -1).finished());
  CHECK(cps1.q == VecX::Constant(2, -1.0));
  CHECK(!cps1.boxed);
  // "5.000000000000000000000000e-0": an exponent of −0 is a number.
  const StoredLcp relay = read_siconos((kSiconosDir / "relay" / "relay_4x4.dat").string(), true);
  CHECK(relay.q(0) == -5.0);
  CHECK(relay.q(3) == 5.0);
  CHECK(relay.lb == VecX::Constant(4, -1.0));
  CHECK(relay.ub == VecX::Constant(4, 1.0));
}

TEST_CASE("the Siconos reader tells LCP and relay files apart by their contents", "[siconos]") {
  // n² + n numbers after the header: an LCP; n² + 3n: a relay problem. Wherever the file is.
  for (const char* folder : {"lcp", "relay"}) {
    for (const fs::path& file : dat_files(kSiconosDir / folder)) {
      if (file.filename().string().find("_block") != std::string::npos) continue;  // storage 1
      CAPTURE(file.filename().string());
      CHECK(read_siconos(file.string(), SiconosKind::Auto).boxed ==
            (std::string(folder) == "relay"));
    }
  }
  const std::string own = std::string(CBPS_SOURCE_DIR) + "/fuzz/corpus/siconos/cbps_relay_2x2.dat";
  CHECK(read_siconos(own, SiconosKind::Auto).boxed);
  // A count that fits neither is refused, saying what each would need.
  std::istringstream odd("2 0 2 2 2 2  1 0 0 1  -1 -1  0 0 1 1 7");
  try {
    parse_siconos(odd, "odd.dat", SiconosKind::Auto);
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("11 numbers after the header") != std::string::npos);
    CHECK(std::string(e.what()).find("6 for an LCP") != std::string::npos);
    CHECK(std::string(e.what()).find("10 for a relay") != std::string::npos);
  }
  CHECK(parse_siconos_kind("relay", "--siconos") == SiconosKind::Relay);
  CHECK_THROWS_AS(parse_siconos_kind("boxed", "--siconos"), InputError);
}

TEST_CASE("the Siconos reader names the file and line of bad input", "[siconos]") {
  struct Case {
    std::string name, text, expected;
  };
  const std::vector<Case> cases = {
      {"missing_q", "2\n0\n2\n2\n2 2\n1 0\n0 1\n-1\n", ": line 8: end of file where q[1]"},
      {"not_number", "2\n0\n2\n2\n2 2\n1 0\n0 x1\n-1 -1\n", ": line 7: expected a number M(1, 1)"},
      {"not_number_2", "2\n0\n2\n2\n2 2\n1 y\n0 1\n-1 -1\n", ": line 6: expected a number M(1, 0)"},
      {"sparse_block", "2\n1\n2\n2\n1\n", ": line 2: storage type 1"},
      {"zero_size", "0\n0\n0\n0\n0 0\n", ": line 1: n = 0"},
      {"huge_size", "100000000\n0\n", ": line 1: n = 100000000"},
      {"wrong_cols", "2\n0\n2\n3\n2 2\n", ": line 4: columns of M = 3"},
      {"non_finite", "1\n0\n1\n1\n1 1\ninf\n-1\n", ": line 6: M(0, 0) is not finite"},
      {"nan", "1\n0\n1\n1\n1 1\n1\nnan\n", ": line 7: q[0] is not finite"},
      {"extra_numbers", "1\n0\n1\n1\n1 1\n1\n-1\n0 1\n", ": line 8: a number ('0') after q"},
      {"n_not_integer", "2.5\n0\n", ": line 1: expected an integer n"},
  };
  for (const Case& c : cases) {
    const std::string path = temp_file(c.name, c.text);
    CAPTURE(c.name);
    CHECK_THROWS_WITH(read_siconos(path, false), Catch::Contains(path + c.expected));
    fs::remove(path);
  }
  CHECK_THROWS_AS(read_siconos("/nonexistent/cbps.dat", false), InputError);
  // An LCP file read as relay runs out of numbers at lb.
  const std::string lcp_as_relay = temp_file("lcp_as_relay", "1\n0\n1\n1\n1 1\n1\n-1\nRemark\n");
  CHECK_THROWS_WITH(read_siconos(lcp_as_relay, true),
                    Catch::Contains(": line 8: expected a number lb[0], found 'Remark'"));
  fs::remove(lcp_as_relay);
  // Free text after the data is not read.
  const std::string remark = temp_file("remark", "1\n0\n1\n1\n1 1\n2\n-1\n\nRemark 4.1 CPS\n");
  CHECK(read_siconos(remark, false).q(0) == -1.0);
  fs::remove(remark);
}
