#include "cgamesh/session/script.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/text_values.hpp"

namespace cgamesh::session {
namespace {

/// Arguments an action takes: words after the verb, not counting the optional flag and open=W.
struct Grammar {
  int min_words = 0;
  int max_words = 0;           ///< −1: any number
  const char* flag = nullptr;  ///< an optional bare word (cap, wall)
  bool open = false;           ///< takes open=W
  bool session = false;        ///< carried out by apply()
};

const std::map<std::string, Grammar>& grammar() {
  static const std::map<std::string, Grammar> g{
      {"clip", {1, 1, nullptr, false, true}},
      {"time", {1, 1, nullptr, false, true}},
      {"play", {1, 1}},
      {"blend", {1, 1, nullptr, false, true}},
      {"skinning", {1, 1}},
      {"color", {1, 1}},
      {"view", {1, 1}},
      {"explode", {1, 1}},
      {"wait", {1, 1}},
      {"joint", {1, 1, nullptr, false, true}},
      {"unedit", {0, 0, nullptr, false, true}},
      {"morph", {1, 1, nullptr, false, true}},
      {"unmorph", {0, 0, nullptr, false, true}},
      {"key", {0, 0, nullptr, false, true}},
      {"generate", {0, 1, nullptr, false, true}},
      {"cut", {1, 1, "cap", false, true}},
      {"tear", {2, -1, nullptr, true, true}},
      {"drag", {2, -1, nullptr, true}},
      {"drill", {3, 3, "wall", false, true}},
      {"tissue", {1, 1, nullptr, false, true}},
      {"bake", {0, 0, nullptr, false, true}},
      {"undo", {0, 0, nullptr, false, true}},
      {"redo", {0, 0, nullptr, false, true}},
      {"reset", {0, 0, nullptr, false, true}},
      {"save", {1, 1}},
      {"screenshot", {1, 1, "panel"}},
      {"deform", {0, 0}},
      {"quit", {0, 0}},
  };
  return g;
}

/// Words of a line; "double quoted" words may hold spaces; # starts a comment.
std::vector<std::string> split_words(const std::string& line, const std::string& where) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < line.size()) {
    if (std::isspace(static_cast<unsigned char>(line[i])) != 0) {
      ++i;
    } else if (line[i] == '#') {
      break;
    } else if (line[i] == '"') {
      const std::size_t end = line.find('"', i + 1);
      if (end == std::string::npos) throw InvalidInputError(where + "a quote is not closed");
      out.push_back(line.substr(i + 1, end - i - 1));
      i = end + 1;
    } else {
      std::size_t end = i;
      while (end < line.size() && std::isspace(static_cast<unsigned char>(line[end])) == 0) ++end;
      out.push_back(line.substr(i, end - i));
      i = end;
    }
  }
  return out;
}

std::string verb_list() {
  std::string out;
  for (const auto& [verb, g] : grammar()) out += (out.empty() ? "" : ", ") + verb;
  return out;
}

Eigen::Vector3d vec3(const std::vector<double>& v, std::size_t at) { return {v[at], v[at + 1], v[at + 2]}; }

ScriptAction parse_line(std::vector<std::string> words, int line, const std::string& where) {
  ScriptAction a;
  a.line = line;
  a.verb = words.front();
  const auto it = grammar().find(a.verb);
  if (it == grammar().end())
    throw InvalidInputError(where + "unknown action '" + a.verb + "' (actions: " + verb_list() + ")");
  const Grammar& g = it->second;
  words.erase(words.begin());
  if (g.flag != nullptr) {
    const auto f = std::find(words.begin(), words.end(), g.flag);
    if (f != words.end()) {
      a.flag = true;
      words.erase(f);
    }
  }
  if (g.open) {
    const auto o =
        std::find_if(words.begin(), words.end(), [](const std::string& w) { return w.rfind("open=", 0) == 0; });
    if (o != words.end()) {
      a.open = io::parse_numbers(o->substr(5), 1, "open")[0];
      if (a.open < 0) throw InvalidInputError(where + "open: the opening width must be >= 0");
      words.erase(o);
    }
  }
  const int n = static_cast<int>(words.size());
  if (n < g.min_words || (g.max_words >= 0 && n > g.max_words))
    throw InvalidInputError(where + a.verb + ": expected " +
                            (g.min_words == g.max_words ? std::to_string(g.min_words)
                             : g.max_words < 0          ? "at least " + std::to_string(g.min_words)
                                               : std::to_string(g.min_words) + " or " + std::to_string(g.max_words)) +
                            " arguments, got " + std::to_string(n));
  const auto one_number = [&](double lo, double hi) {
    const double v = io::parse_numbers(words[0], 1, a.verb)[0];
    if (v < lo || v > hi)
      throw InvalidInputError(where + a.verb + ": " + words[0] + " is outside [" + io::number(lo) + ", " +
                              io::number(hi) + "]");
    a.numbers = {v};
  };
  if (a.verb == "time" || a.verb == "play") {
    one_number(0, 1e9);
  } else if (a.verb == "explode") {
    one_number(0, 100);
  } else if (a.verb == "wait") {
    one_number(1, 10000);
    if (a.numbers[0] != std::floor(a.numbers[0])) throw InvalidInputError(where + "wait: a whole number of frames");
  } else if (a.verb == "cut") {
    a.numbers = io::parse_numbers(words[0], 4, "cut NX,NY,NZ,D");
  } else if (a.verb == "tear") {
    for (const std::string& w : words) {
      const auto v = io::parse_numbers(w, 6, "tear HX,HY,HZ,TX,TY,TZ");
      a.scalpels.push_back({vec3(v, 0), vec3(v, 3)});
    }
  } else if (a.verb == "drag") {
    for (const std::string& w : words) {
      const auto v = io::parse_numbers(w, 2, "drag X,Y");
      a.points.emplace_back(v[0], v[1]);
    }
  } else if (a.verb == "drill") {
    const auto tip = io::parse_numbers(words[0], 3, "drill TIP"), base = io::parse_numbers(words[1], 3, "drill BASE");
    a.numbers = {tip[0], tip[1], tip[2], base[0], base[1], base[2], io::parse_numbers(words[2], 1, "drill RADIUS")[0]};
  } else if (a.verb == "blend") {
    if (!io::kBlendModes.contains(words[0])) throw InvalidInputError(where + "blend: expected format, linear or log");
    a.text = words[0];
  } else if (a.verb == "morph") {
    try {
      (void)io::parse_morph_setting(words[0]);
    } catch (const InvalidInputError& e) {
      throw InvalidInputError(where + "morph: " + e.what());
    }
    a.text = words[0];
  } else if (a.verb == "tissue") {
    a.text = words[0];
    if (a.text != "off") {
      a.numbers = io::parse_numbers(words[0], 1, "tissue TENSION");
      if (!(a.numbers[0] >= 0 && a.numbers[0] < 1))
        throw InvalidInputError(where + "tissue: the tension is a fraction in [0, 1), or 'off'");
    }
  } else if (a.verb == "skinning") {
    if (!io::kSkinningModes.contains(words[0]))
      throw InvalidInputError(where + "skinning: expected cga, versor, matrix or dqs");
    a.text = words[0];
  } else if (n > 0) {
    a.text = words[0];
  }
  return a;
}

}  // namespace

std::vector<ScriptAction> parse_script(const std::string& text, const std::string& source) {
  std::vector<ScriptAction> out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string where = source + ":" + std::to_string(number) + ": ";
    std::vector<std::string> words = split_words(line, where);
    if (words.empty()) continue;
    try {
      out.push_back(parse_line(std::move(words), number, where));
    } catch (const InvalidInputError& e) {
      const std::string what = e.what();
      if (what.rfind(where, 0) == 0) throw;
      throw InvalidInputError(where + what);
    }
  }
  return out;
}

std::vector<ScriptAction> read_script(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError("cannot read the script '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw FileError("cannot read the script '" + path + "'");
  return parse_script(text.str(), path);
}

bool is_session_action(const std::string& verb) noexcept {
  const auto it = grammar().find(verb);
  return it != grammar().end() && it->second.session;
}

std::optional<OperationReport> apply(Session& session, const ScriptAction& a) {
  const anim::RiggedModel& model = session.model();
  if (a.verb == "clip") {
    session.set_clip(a.text == "bind" ? -1 : io::clip_index(model, a.text));
  } else if (a.verb == "time") {
    session.set_time(a.numbers[0]);
  } else if (a.verb == "blend") {
    session.set_blend(io::kBlendModes.at(a.text));
  } else if (a.verb == "joint") {
    const anim::JointEdit parsed = io::parse_edit(model.skeleton, a.text, io::max_translation(model));
    // One part of the joint's edit changes; the others stay.
    anim::JointEdit e = session.edit_of(parsed.joint);
    const std::string kind = a.text.substr(a.text.rfind(':') + 1);
    if (kind.rfind("rotate=", 0) == 0) {
      e.axis = parsed.axis;
      e.angle = parsed.angle;
    } else if (kind.rfind("translate=", 0) == 0) {
      e.translation = parsed.translation;
    } else {
      e.scale = parsed.scale;
    }
    session.set_edit(e);
  } else if (a.verb == "unedit") {
    session.clear_edits();
  } else if (a.verb == "morph") {
    const anim::MorphSetting m = io::parse_morph_setting(a.text);
    session.set_morph_weight(m.target, m.weight);
  } else if (a.verb == "unmorph") {
    session.clear_morph_weights();
  } else if (a.verb == "key") {
    session.add_key();
  } else if (a.verb == "generate") {
    session.generate_clip(a.text.empty() ? "generated" : a.text);
  } else if (a.verb == "cut") {
    surgery::CutOptions o;
    o.cap = a.flag;
    return session.cut(vec3(a.numbers, 0), a.numbers[3], o);
  } else if (a.verb == "tear") {
    surgery::TearOptions o;
    o.open = a.open;
    return session.tear(a.scalpels, o);
  } else if (a.verb == "drill") {
    surgery::DrillOptions o;
    o.wall = a.flag;
    return session.drill(vec3(a.numbers, 0), vec3(a.numbers, 3), a.numbers[6], o);
  } else if (a.verb == "tissue") {
    if (a.text == "off") {
      session.set_tissue(std::nullopt);
    } else {
      soft::TissueOptions o = session.tissue() != nullptr ? session.tissue()->options() : soft::TissueOptions{};
      o.pretension = a.numbers[0];
      session.set_tissue(o);
    }
  } else if (a.verb == "bake") {
    return session.bake_tissue();
  } else if (a.verb == "undo") {
    session.undo();
  } else if (a.verb == "redo") {
    session.redo();
  } else if (a.verb == "reset") {
    session.reset();
  } else {
    throw InvalidInputError("'" + a.verb + "' is not an action on the model (the viewer carries it out)");
  }
  return std::nullopt;
}

}  // namespace cgamesh::session
