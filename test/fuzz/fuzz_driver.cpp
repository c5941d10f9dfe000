// The in-tree fuzz driver (gcc, no libFuzzer): every file of the target's seed corpus, then
// deterministic mutations of them (byte flips, insertions, deletions, repeats, splices and
// tokens that broke loaders before: NaN, Inf, huge numbers, brackets). A crash fails the
// test by ending the process; a slow input fails it by the time limit. SV_FUZZ_RUNS sets
// the number of mutations (default 3000).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fuzz_target.h"

namespace {

std::vector<std::string> readCorpus(const std::string& dir) {
  std::vector<std::filesystem::path> paths;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.is_regular_file()) paths.push_back(entry.path());
  }
  std::sort(paths.begin(), paths.end());
  std::vector<std::string> out;
  for (const auto& p : paths) {
    std::ifstream in(p, std::ios::binary);
    out.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return out;
}

std::string mutate(const std::vector<std::string>& corpus, std::mt19937_64& rng) {
  static const std::vector<std::string> kTokens = {".nan",
                                                   ".inf",
                                                   "-.inf",
                                                   "nan",
                                                   "1e308",
                                                   "-1e308",
                                                   "1e9",
                                                   "99999999999",
                                                   "-1",
                                                   "0",
                                                   "-0",
                                                   "2147483648",
                                                   "[",
                                                   "]",
                                                   "{",
                                                   "}",
                                                   ":",
                                                   ", ",
                                                   "\n",
                                                   "- ",
                                                   "\"",
                                                   "'",
                                                   "&a",
                                                   "*a",
                                                   "!!binary",
                                                   "\xff\xff\xff\x7f",
                                                   std::string(1, '\0')};
  auto pick = [&](std::size_t n) { return n == 0 ? std::size_t(0) : std::size_t(rng() % n); };
  std::string s = corpus[pick(corpus.size())];
  const int edits = 1 + static_cast<int>(pick(4));
  for (int e = 0; e < edits; ++e) {
    switch (pick(7)) {
      case 0:  // flip a byte
        if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1 << pick(8));
        break;
      case 1:  // a random byte
        s.insert(s.begin() + static_cast<long>(pick(s.size() + 1)), static_cast<char>(rng()));
        break;
      case 2: {  // delete a range
        const std::size_t at = pick(s.size() + 1), n = pick(16) + 1;
        s.erase(std::min(at, s.size()), n);
        break;
      }
      case 3: {  // repeat a range
        const std::size_t at = pick(s.size() + 1), n = pick(64) + 1;
        const std::string part = s.substr(std::min(at, s.size()), n);
        for (std::size_t k = 0, times = pick(8) + 1; k < times; ++k) s.insert(std::min(at, s.size()), part);
        break;
      }
      case 4:  // a token
        s.insert(pick(s.size() + 1), kTokens[pick(kTokens.size())]);
        break;
      case 5: {  // replace a number-like run by a token
        const std::size_t at = pick(s.size() + 1);
        std::size_t end = at;
        while (end < s.size() &&
               (std::isdigit(static_cast<unsigned char>(s[end])) || s[end] == '.' || s[end] == '-'))
          ++end;
        s.replace(at, end - at, kTokens[pick(12)]);
        break;
      }
      default: {  // splice with another seed
        const std::string& other = corpus[pick(corpus.size())];
        s = s.substr(0, pick(s.size() + 1)) + other.substr(pick(other.size() + 1));
        break;
      }
    }
  }
  return s;
}

double run(const std::string& input) {
  const auto start = std::chrono::steady_clock::now();
  LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(Fuzz, SeedCorpusAndDeterministicMutationsEndInAResultOrAClearError) {
  const std::vector<std::string> corpus = readCorpus(SV_FUZZ_CORPUS);
  ASSERT_FALSE(corpus.empty()) << "no seed corpus in " << SV_FUZZ_CORPUS;
  const char* env = std::getenv("SV_FUZZ_RUNS");
  const long runs = env ? std::atol(env) : 3000;
  double slowest = 0;
  std::string slowest_input;
  for (const std::string& seed : corpus) {
    const double t = run(seed);
    if (t > slowest) slowest = t, slowest_input = seed;
  }
  std::mt19937_64 rng(20261202);
  for (long i = 0; i < runs; ++i) {
    const std::string input = mutate(corpus, rng);
    const double t = run(input);
    if (t > slowest) slowest = t, slowest_input = input;
  }
  std::printf("[ fuzz ] %s: %zu seeds + %ld mutations, slowest input %.1f ms (%zu bytes)\n", SV_FUZZ_CORPUS,
              corpus.size(), runs, slowest * 1e3, slowest_input.size());
  // A hang is a finding as much as a crash: no input may take a second.
  EXPECT_LT(slowest, 1.0) << "slowest input (" << slowest_input.size()
                          << " bytes): " << slowest_input.substr(0, 200);
}

}  // namespace
