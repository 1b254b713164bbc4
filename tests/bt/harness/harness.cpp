// schemalog's BT.CPP harness: a BehaviorTree.CPP 4 tree run in the real BT.CPP with its node
// types registered from TreeNodesModel files, ports and all, the leaves scripted by draws.
//
//   harness --tree FILE... [--models FILE]... [--main ID] [--draws FILE] [--max-ticks N]
//           [--stateful] [--load-only] [--enum NAME=INT]... [--substitutions FILE] [--paths]
//           [--blackboard]
//
// FILE is loaded with registerBehaviorTreeFromFile (its <include>s relative to it); --tree given
// again loads each file so, in order, into the one factory (as Nav2 and BehaviorTree.ROS2 load a
// folder); the main tree is --main, else BT.CPP's choice (the first file's main_tree_to_execute,
// else the only tree). Every node type a
// --models file declares (<TreeNodesModel><Action ID=..><input_port name=../>..) and BT.CPP does
// not register itself is registered with a TreeNodeManifest holding its declared ports (any
// type, no default: a port the XML does not write stays unset, so the ports a node reports are
// exactly the ones its element writes), as:
//   Action     a scripted leaf: each tick takes the next draw, (SUCCESS, FAILURE, RUNNING)[d % 3];
//              re-ticked every time, as a SyncActionNode or Nav2's BtActionNode is (the model's
//              default Action rule); with --stateful a StatefulActionNode (onStart/onRunning take
//              a draw, a completed one its parent did not reset returns its last status:
//              STATEFUL_ACTION). A RUNNING one halted reports the halt.
//   Condition  a ConditionNode: (SUCCESS, FAILURE)[d % 2].
//   Control, Decorator  Nav2's own nodes as written below from Nav2's source (PipelineSequence,
//              RecoveryNode, RoundRobin, RateController, and the time- or goal-driven decorators),
//              else an opaque node that lets the draws choose (schemalog's bt/semantics.py _opaque).
// Nav2's controls and decorators are registered even when no model declares them.
//
// --draws FILE: one run per line, `LABEL d0 d1 d2 ...`: the k-th decision of the run (a leaf
// tick, a RateController's "period elapsed?", a gate or choice of an opaque node) takes d_k.
// Without --draws, one run reads its draws from stdin's first line. Each run creates the tree
// anew, ticks it with tickExactlyOnce until the root completes or --max-ticks (default 12) root
// ticks, then (still RUNNING) haltTree. Output, one JSON object a line:
//   {"ev":"run","label":"3"}
//   {"ev":"tick","type":"FollowPath","name":"FollowPath","ports":{"path":"{path}"},"out":"RUNNING"}
//   {"ev":"halt","type":..,"name":..,"ports":{..}}
//   {"ev":"time","type":"RateController",..,"out":true}          (the period elapsed, or not)
//   {"ev":"choose","type":"GoalUpdater",..,"out":0}               (an opaque node ticks child 0)
//   {"ev":"choose","type":"GoalUpdater",..,"out":"SUCCESS"}       (.. then returns SUCCESS)
//   {"ev":"root","status":"RUNNING"}    .. "SUCCESS", "FAILURE"; "HALTED" after haltTree
//   {"ev":"error","what":".."}          BT.CPP threw while ticking: the run ends
//   {"ev":"missing","type":..,"name":..,"port":"goal","what":".."}   (--blackboard: getInput failed)
// --blackboard: a scripted leaf, when ticked, first reads each input port its element binds to a
// blackboard entry (`{x}`) with getInput<std::string>, reporting one that fails (the entry not
// there: what Nav2's nodes meet as "Any::cast failed because it is empty" or a missing key), then
// writes each such output port (setOutput): a ticked writer writes, as schemalog lint assumes.
// A tree BT.CPP refuses to load: {"ev":"load_error","what":".."} and exit status 3.
// --load-only: load and create the main tree, print {"ev":"loaded","main":".."}, exit.
// --enum NAME=INT: a scripting enum (registerScriptingEnum), as a program registers them
// (BT.CPP's scripting tutorial: THE_ANSWER, RED, BLUE, GREEN).
// --substitutions FILE: substitution rules in the JSON BT.CPP reads with
// loadSubstitutionRuleFromJSON (BT.CPP's t15 example), applied to every tree created. A rule's
// node ID must be registered (a --models entry: a scripted leaf whose events carry the
// substituted node's type, BT.CPP setting it back); a TestNodeConfig makes a BT::TestNode,
// which reports no event.
// --paths: with --load-only, before the "loaded" line, each node of the main tree in BT.CPP's
// visiting order (t15's applyVisitor), {"ev":"node","path":"mysub/action_subA","name":..,
// "type":..}, with "by":"TestNode" or "by":"DummyAction" on a node a substitution rule made.
//
// Written for schemalog (tests/bt/test_btcpp_harness.py); Nav2's nodes below are our renditions
// of the behaviour of ros-navigation/navigation2's nav2_behavior_tree/plugins, not its code.

#include <algorithm>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "behaviortree_cpp/action_node.h"
#include "behaviortree_cpp/actions/test_node.h"
#include "behaviortree_cpp/bt_factory.h"
#include "behaviortree_cpp/condition_node.h"
#include "behaviortree_cpp/control_node.h"
#include "behaviortree_cpp/decorator_node.h"
#include "tinyxml2/tinyxml2.h"

namespace {

using BT::NodeStatus;

// ---------------------------------------------------------------------------------------------
// The environment: the draws of the current run, and the output

struct Env {
  std::vector<long> draws;
  size_t k = 0;
  bool recording = false;
  std::string out;

  long next() {
    if (k >= draws.size()) {
      throw std::runtime_error("draws exhausted after " + std::to_string(k) + " decisions");
    }
    return draws[k++];
  }
};

Env env;

// the registration ID whose builder made each node of ours (a substitution rule's ID differs
// from the one BT.CPP then sets, the node's own)
std::map<const BT::TreeNode*, std::string> built_as;

std::string json_string(const std::string& s) {
  std::string r = "\"";
  for (unsigned char c : s) {
    switch (c) {
      case '"': r += "\\\""; break;
      case '\\': r += "\\\\"; break;
      case '\n': r += "\\n"; break;
      case '\r': r += "\\r"; break;
      case '\t': r += "\\t"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          r += buf;
        } else {
          r += static_cast<char>(c);
        }
    }
  }
  return r + "\"";
}

const char* status_name(NodeStatus s) {
  switch (s) {
    case NodeStatus::IDLE: return "IDLE";
    case NodeStatus::RUNNING: return "RUNNING";
    case NodeStatus::SUCCESS: return "SUCCESS";
    case NodeStatus::FAILURE: return "FAILURE";
    case NodeStatus::SKIPPED: return "SKIPPED";
  }
  return "?";
}

// The ports a node's element writes (input, output and inout: BT.CPP puts an inout in both)
std::string ports_json(const BT::TreeNode& node) {
  std::map<std::string, std::string> ports;
  for (const auto& [k, v] : node.config().input_ports) ports[k] = v;
  for (const auto& [k, v] : node.config().output_ports) ports[k] = v;
  std::string r = "{";
  bool first = true;
  for (const auto& [k, v] : ports) {
    if (!first) r += ",";
    first = false;
    r += json_string(k) + ":" + json_string(v);
  }
  return r + "}";
}

void emit(const char* ev, const BT::TreeNode& node, const std::string& out_json = "") {
  if (!env.recording) return;
  env.out += std::string("{\"ev\":\"") + ev + "\",\"type\":" + json_string(node.registrationName()) +
             ",\"name\":" + json_string(node.name()) + ",\"ports\":" + ports_json(node);
  if (!out_json.empty()) env.out += ",\"out\":" + out_json;
  env.out += "}\n";
}

void emit_line(const std::string& line) {
  env.out += line + "\n";
}

std::string quoted(NodeStatus s) { return std::string("\"") + status_name(s) + "\""; }

// ---------------------------------------------------------------------------------------------
// Leaves

const NodeStatus ACTION_OUTCOMES[] = {NodeStatus::SUCCESS, NodeStatus::FAILURE, NodeStatus::RUNNING};
const NodeStatus CONDITION_OUTCOMES[] = {NodeStatus::SUCCESS, NodeStatus::FAILURE};

bool blackboard_io = false;       // --blackboard

void touch_blackboard(BT::TreeNode& node) {
  if (!blackboard_io) return;
  const BT::NodeConfig& config = static_cast<const BT::TreeNode&>(node).config();
  for (const auto& [port, value] : config.input_ports) {
    if (!BT::TreeNode::isBlackboardPointer(value)) continue;
    std::string got;
    auto read = node.getInput<std::string>(port, got);
    if (!read && env.recording) {
      env.out += std::string("{\"ev\":\"missing\",\"type\":") + json_string(node.registrationName()) +
                 ",\"name\":" + json_string(node.name()) + ",\"port\":" + json_string(port) +
                 ",\"what\":" + json_string(read.error()) + "}\n";
    }
  }
  for (const auto& [port, value] : config.output_ports) {
    if (BT::TreeNode::isBlackboardPointer(value)) (void)node.setOutput(port, std::string("written"));
  }
}

NodeStatus draw_action(BT::TreeNode& node) {
  touch_blackboard(node);
  NodeStatus s = ACTION_OUTCOMES[env.next() % 3];
  emit("tick", node, quoted(s));
  return s;
}

// An action re-ticked every time (SyncActionNode's tick, or Nav2's BtActionNode as the model
// sees it), which may return RUNNING; a RUNNING one halted reports it.
class ScriptedAction : public BT::ActionNodeBase {
 public:
  ScriptedAction(const std::string& name, const BT::NodeConfig& config)
      : BT::ActionNodeBase(name, config) {}
  NodeStatus tick() override { return draw_action(*this); }
  void halt() override {
    // Tree::haltTree halts every node after the root: only a RUNNING one is halted for real
    if (status() == NodeStatus::RUNNING) emit("halt", *this);
    resetStatus();
  }
};

class ScriptedStatefulAction : public BT::StatefulActionNode {
 public:
  ScriptedStatefulAction(const std::string& name, const BT::NodeConfig& config)
      : BT::StatefulActionNode(name, config) {}
  NodeStatus onStart() override { return draw_action(*this); }
  NodeStatus onRunning() override { return draw_action(*this); }
  void onHalted() override { emit("halt", *this); }
};

class ScriptedCondition : public BT::ConditionNode {
 public:
  ScriptedCondition(const std::string& name, const BT::NodeConfig& config)
      : BT::ConditionNode(name, config) {}
  NodeStatus tick() override {
    touch_blackboard(*this);
    NodeStatus s = CONDITION_OUTCOMES[env.next() % 2];
    emit("tick", *this, quoted(s));
    return s;
  }
};

// ---------------------------------------------------------------------------------------------
// Nav2's controls (nav2_behavior_tree/plugins/control/), as their source behaves

// PipelineSequence: every tick ticks the children from the first; a SUCCESS or SKIPPED goes on,
// a RUNNING child at or past the furthest one that ran stops the tick (one before it goes on), a
// FAILURE halts all children and fails; after the last child, halt all children and succeed (or
// skip, when every child was skipped).
class PipelineSequence : public BT::ControlNode {
 public:
  PipelineSequence(const std::string& name, const BT::NodeConfig& config)
      : BT::ControlNode(name, config) {}
  NodeStatus tick() override {
    size_t skipped = 0;
    for (size_t i = 0; i < children_nodes_.size(); ++i) {
      const NodeStatus s = children_nodes_[i]->executeTick();
      if (s == NodeStatus::SKIPPED) {
        ++skipped;
        continue;
      }
      if (s == NodeStatus::FAILURE) {
        haltChildren();
        last_ = 0;
        return s;
      }
      if (s == NodeStatus::RUNNING) {
        if (i >= last_) {
          last_ = i;
          return s;
        }
        continue;
      }
      if (s != NodeStatus::SUCCESS) {
        throw std::runtime_error(std::string("PipelineSequence: invalid child status ") + status_name(s));
      }
    }
    haltChildren();
    last_ = 0;
    return skipped == children_nodes_.size() ? NodeStatus::SKIPPED : NodeStatus::SUCCESS;
  }
  void halt() override {
    ControlNode::halt();
    last_ = 0;
  }

 private:
  size_t last_ = 0;
};

// RecoveryNode: tick the first child; when it fails and retries are left, halt it and tick the
// second (the recovery); the recovery's success counts a retry and goes back to the first.
// The first child's success, the recovery's failure, or no retry left: reset and return.
// A skipped first child skips the node (reset); a skipped recovery fails it, back at the first
// child, the retries counted so far kept.
class RecoveryNode : public BT::ControlNode {
 public:
  RecoveryNode(const std::string& name, const BT::NodeConfig& config)
      : BT::ControlNode(name, config) {}
  NodeStatus tick() override {
    int retries = 1;
    (void)getInput("number_of_retries", retries);
    if (children_nodes_.size() != 2) {
      throw BT::BehaviorTreeException("Recovery Node '" + name() + "' must only have 2 children.");
    }
    setStatus(NodeStatus::RUNNING);
    while (idx_ < 2 && count_ <= retries) {
      const NodeStatus s = children_nodes_[idx_]->executeTick();
      if (idx_ == 0) {
        if (s == NodeStatus::SKIPPED) {
          halt();
          return NodeStatus::SKIPPED;
        }
        if (s == NodeStatus::SUCCESS) {
          halt();
          return NodeStatus::SUCCESS;
        }
        if (s == NodeStatus::RUNNING) return s;
        if (s != NodeStatus::FAILURE) throw BT::LogicError("A child node must never return IDLE");
        if (count_ < retries) {
          haltChild(0);
          idx_ = 1;
        } else {
          halt();
          return NodeStatus::FAILURE;
        }
      } else {
        if (s == NodeStatus::SKIPPED) {
          idx_ = 0;
          haltChild(1);
          return NodeStatus::FAILURE;
        }
        if (s == NodeStatus::RUNNING) return s;
        if (s == NodeStatus::SUCCESS) {
          haltChild(1);
          ++count_;
          idx_ = 0;
        } else if (s == NodeStatus::FAILURE) {
          halt();
          return NodeStatus::FAILURE;
        } else {
          throw BT::LogicError("A child node must never return IDLE");
        }
      }
    }
    halt();
    return NodeStatus::FAILURE;
  }
  void halt() override {
    ControlNode::halt();
    count_ = 0;
    idx_ = 0;
  }

 private:
  size_t idx_ = 0;
  int count_ = 0;
};

// RoundRobin: tick from the child after the last one that succeeded; a SUCCESS halts all the
// children and succeeds (the index stays past it), a FAILURE moves on; every child failed in
// turn: halt them all, start from the first again, and fail.
class RoundRobin : public BT::ControlNode {
 public:
  RoundRobin(const std::string& name, const BT::NodeConfig& config)
      : BT::ControlNode(name, config) {}
  NodeStatus tick() override {
    const size_t n = children_nodes_.size();
    setStatus(NodeStatus::RUNNING);
    while (failed_ < n) {
      const NodeStatus s = children_nodes_[idx_]->executeTick();
      if (s == NodeStatus::SUCCESS) {
        if (++idx_ >= n) idx_ = 0;
        failed_ = 0;
        haltChildren();
        return s;
      }
      if (s == NodeStatus::FAILURE) {
        if (++idx_ >= n) idx_ = 0;
        ++failed_;
      } else if (s == NodeStatus::RUNNING) {
        return s;
      } else {
        throw BT::LogicError("Invalid status return from BT node");
      }
    }
    haltChildren();
    idx_ = 0;
    failed_ = 0;
    return NodeStatus::FAILURE;
  }
  void halt() override {
    ControlNode::halt();
    idx_ = 0;
    failed_ = 0;
  }

 private:
  size_t idx_ = 0;
  size_t failed_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Nav2's decorators (nav2_behavior_tree/plugins/decorator/)

NodeStatus completed_or_failure(NodeStatus s) {
  return (s == NodeStatus::RUNNING || s == NodeStatus::SUCCESS) ? s : NodeStatus::FAILURE;
}

// RateController: from IDLE the child is ticked at once; later only while it runs or when the
// period elapsed (the draw's choice, (true, false)[d % 2], a "time" event); else RUNNING. The
// child is not reset when it completes; its SKIPPED (or any other) is FAILURE.
class RateController : public BT::DecoratorNode {
 public:
  RateController(const std::string& name, const BT::NodeConfig& config)
      : BT::DecoratorNode(name, config) {}
  NodeStatus tick() override {
    const bool first = status() == NodeStatus::IDLE;
    setStatus(NodeStatus::RUNNING);
    bool go = first || child()->status() == NodeStatus::RUNNING;
    if (!go) {
      go = env.next() % 2 == 0;
      emit("time", *this, go ? "true" : "false");
    }
    if (go) return completed_or_failure(child()->executeTick());
    return status();
  }
};

// An opaque node's choice, as schemalog's model records it: a child to tick, or a status.
void choose_child(const BT::TreeNode& node, size_t i) { emit("choose", node, std::to_string(i)); }
NodeStatus choose_status(const BT::TreeNode& node, NodeStatus s) {
  emit("choose", node, quoted(s));
  return s;
}

// DistanceController, SpeedController, GoalUpdatedController: like RateController, the child is
// ticked from IDLE, while it runs, and when the robot moved far enough / the period (scaled by
// speed) elapsed / the goal changed: that last is a draw here, (true, false)[d % 2]. schemalog's
// model knows none of them (opaque): the harness reports their choices as "choose" events.
class GatedDecorator : public BT::DecoratorNode {
 public:
  GatedDecorator(const std::string& name, const BT::NodeConfig& config)
      : BT::DecoratorNode(name, config) {}
  NodeStatus tick() override {
    const bool first = status() == NodeStatus::IDLE;
    setStatus(NodeStatus::RUNNING);
    if (first || child()->status() == NodeStatus::RUNNING || env.next() % 2 == 0) {
      choose_child(*this, 0);
      return choose_status(*this, completed_or_failure(child()->executeTick()));
    }
    return choose_status(*this, NodeStatus::RUNNING);
  }
};

// GoalUpdater: updates the goal from a topic (nothing a trace sees), then ticks its child and
// returns its status.
class GoalUpdater : public BT::DecoratorNode {
 public:
  GoalUpdater(const std::string& name, const BT::NodeConfig& config)
      : BT::DecoratorNode(name, config) {}
  NodeStatus tick() override {
    choose_child(*this, 0);
    return choose_status(*this, child()->executeTick());
  }
};

// Any other control or decorator a model declares: opaque, each choice a draw among its
// children and the three statuses, d % (children + 3), until it returns a status.
class OpaqueControl : public BT::ControlNode {
 public:
  OpaqueControl(const std::string& name, const BT::NodeConfig& config)
      : BT::ControlNode(name, config) {}
  NodeStatus tick() override {
    const size_t n = children_nodes_.size();
    while (true) {
      const size_t c = static_cast<size_t>(env.next()) % (n + 3);
      if (c >= n) return choose_status(*this, ACTION_OUTCOMES[c - n]);
      choose_child(*this, c);
      children_nodes_[c]->executeTick();
    }
  }
};

class OpaqueDecorator : public BT::DecoratorNode {
 public:
  OpaqueDecorator(const std::string& name, const BT::NodeConfig& config)
      : BT::DecoratorNode(name, config) {}
  NodeStatus tick() override {
    while (true) {
      const size_t c = static_cast<size_t>(env.next()) % 4;
      if (c >= 1) return choose_status(*this, ACTION_OUTCOMES[c - 1]);
      choose_child(*this, 0);
      child()->executeTick();
    }
  }
};

// ---------------------------------------------------------------------------------------------
// Models and registration

struct Model {
  std::string id, kind;
  BT::PortsList ports;
};

std::vector<Model> read_models(const std::string& path) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) {
    throw std::runtime_error("cannot read models file " + path + ": " + doc.ErrorStr());
  }
  std::vector<Model> models;
  const tinyxml2::XMLElement* root = doc.RootElement();
  if (!root) return models;
  const tinyxml2::XMLElement* tnm =
      std::string(root->Name()) == "TreeNodesModel" ? root : root->FirstChildElement("TreeNodesModel");
  for (; tnm; tnm = tnm->NextSiblingElement("TreeNodesModel")) {
    for (auto* e = tnm->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const char* id = e->Attribute("ID");
      if (!id) continue;
      Model m{id, e->Name(), {}};
      for (auto* p = e->FirstChildElement(); p; p = p->NextSiblingElement()) {
        const std::string tag = p->Name();
        const char* pname = p->Attribute("name");
        if (!pname) continue;
        BT::PortDirection dir = tag == "input_port"    ? BT::PortDirection::INPUT
                                : tag == "output_port" ? BT::PortDirection::OUTPUT
                                                       : BT::PortDirection::INOUT;
        m.ports.insert({pname, BT::PortInfo(dir)});      // any type, no default
      }
      models.push_back(m);
    }
  }
  return models;
}

template <typename T>
BT::NodeBuilder builder(const std::string& id) {
  return [id](const std::string& name, const BT::NodeConfig& config) {
    auto node = std::make_unique<T>(name, config);
    built_as[node.get()] = id;
    return node;
  };
}

void register_model(BT::BehaviorTreeFactory& factory, const Model& m, bool stateful) {
  if (factory.builders().count(m.id)) return;          // BT.CPP's own node, or declared twice
  BT::TreeNodeManifest manifest;
  manifest.registration_ID = m.id;
  manifest.ports = m.ports;
  BT::NodeBuilder b;
  if (m.kind == "Action") {
    manifest.type = BT::NodeType::ACTION;
    b = stateful ? builder<ScriptedStatefulAction>(m.id) : builder<ScriptedAction>(m.id);
  } else if (m.kind == "Condition") {
    manifest.type = BT::NodeType::CONDITION;
    b = builder<ScriptedCondition>(m.id);
  } else if (m.kind == "Control") {
    manifest.type = BT::NodeType::CONTROL;
    b = m.id == "PipelineSequence" ? builder<PipelineSequence>(m.id)
        : m.id == "RecoveryNode"   ? builder<RecoveryNode>(m.id)
        : m.id == "RoundRobin"     ? builder<RoundRobin>(m.id)
                                   : builder<OpaqueControl>(m.id);
  } else if (m.kind == "Decorator") {
    manifest.type = BT::NodeType::DECORATOR;
    b = m.id == "RateController"          ? builder<RateController>(m.id)
        : m.id == "GoalUpdater"           ? builder<GoalUpdater>(m.id)
        : (m.id == "DistanceController" || m.id == "SpeedController" ||
           m.id == "GoalUpdatedController") ? builder<GatedDecorator>(m.id)
                                            : builder<OpaqueDecorator>(m.id);
  } else {
    return;                                            // SubTree models: BT.CPP reads them itself
  }
  factory.registerBuilder(manifest, b);
}

std::vector<std::pair<std::string, std::vector<long>>> read_draws(std::istream& in) {
  std::vector<std::pair<std::string, std::vector<long>>> runs;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string label;
    if (!(ss >> label)) continue;
    std::vector<long> draws;
    long d;
    while (ss >> d) draws.push_back(d);
    runs.emplace_back(label, std::move(draws));
  }
  return runs;
}

int usage() {
  std::cerr << "usage: harness --tree FILE... [--models FILE]... [--main ID] [--draws FILE] "
               "[--max-ticks N] [--stateful] [--load-only] [--enum NAME=INT]... [--substitutions FILE] [--blackboard] "
               "[--paths]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string main_id, draws_file, substitutions_file;
  std::vector<std::string> tree_files, models_files;
  std::vector<std::pair<std::string, int>> enums;
  int max_ticks = 12;
  bool stateful = false, load_only = false, paths = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    try {
      if (a == "--tree") tree_files.push_back(value());
      else if (a == "--models") models_files.push_back(value());
      else if (a == "--main") main_id = value();
      else if (a == "--draws") draws_file = value();
      else if (a == "--max-ticks") max_ticks = std::stoi(value());
      else if (a == "--stateful") stateful = true;
      else if (a == "--load-only") load_only = true;
      else if (a == "--substitutions") substitutions_file = value();
      else if (a == "--paths") paths = true;
      else if (a == "--blackboard") blackboard_io = true;
      else if (a == "--enum") {
        const std::string e = value();
        const auto eq = e.find('=');
        if (eq == std::string::npos) throw std::runtime_error("--enum NAME=INT");
        enums.emplace_back(e.substr(0, eq), std::stoi(e.substr(eq + 1)));
      }
      else return usage();
    } catch (const std::exception& e) {
      std::cerr << e.what() << "\n";
      return usage();
    }
  }
  if (tree_files.empty()) return usage();
  for (auto& f : tree_files) f = std::filesystem::absolute(f).string();   // BT.CPP resolves <include>s from its directory

  BT::BehaviorTreeFactory factory;
  std::string nodes;                                   // --paths: the main tree's nodes
  try {
    // Nav2's nodes, also where no model declares them (a model's ports take precedence)
    std::vector<Model> models;
    for (const auto& f : models_files) {
      auto more = read_models(f);
      models.insert(models.end(), more.begin(), more.end());
    }
    for (const auto& m : models) register_model(factory, m, stateful);
    for (const auto& m : std::vector<Model>{
             {"PipelineSequence", "Control", {}},
             {"RecoveryNode", "Control", {{"number_of_retries", BT::PortInfo(BT::PortDirection::INPUT)}}},
             {"RoundRobin", "Control", {}},
             {"RateController", "Decorator", {{"hz", BT::PortInfo(BT::PortDirection::INPUT)}}}}) {
      register_model(factory, m, stateful);
    }
    for (const auto& [name, v] : enums) factory.registerScriptingEnum(name, v);
    if (!substitutions_file.empty()) {
      std::ifstream in(substitutions_file);
      if (!in) throw std::runtime_error("cannot read " + substitutions_file);
      std::stringstream text;
      text << in.rdbuf();
      factory.loadSubstitutionRuleFromJSON(text.str());
    }
    for (const auto& f : tree_files) factory.registerBehaviorTreeFromFile(f);
    built_as.clear();
    auto probe = factory.createTree(main_id);      // "": BT.CPP picks the main tree
    if (main_id.empty()) main_id = probe.subtrees.front()->tree_ID;
    if (paths) {
      probe.applyVisitor([&](BT::TreeNode* node) {
        std::string by;
        if (dynamic_cast<const BT::TestNode*>(node)) by = "TestNode";
        else if (built_as.count(node) && built_as[node] != node->registrationName()) by = built_as[node];
        nodes += "{\"ev\":\"node\",\"path\":" + json_string(node->fullPath()) + ",\"name\":" +
                 json_string(node->name()) + ",\"type\":" + json_string(node->registrationName()) +
                 (by.empty() ? "" : ",\"by\":" + json_string(by)) + "}\n";
      });
    }
  } catch (const std::exception& e) {
    std::cout << "{\"ev\":\"load_error\",\"what\":" << json_string(e.what()) << "}\n";
    return 3;
  }
  if (load_only) {
    std::cout << nodes << "{\"ev\":\"loaded\",\"main\":" << json_string(main_id) << "}\n";
    return 0;
  }

  std::vector<std::pair<std::string, std::vector<long>>> runs;
  if (draws_file.empty()) {
    runs = read_draws(std::cin);
    if (runs.size() > 1) runs.resize(1);
  } else {
    std::ifstream in(draws_file);
    if (!in) {
      std::cerr << "cannot read " << draws_file << "\n";
      return 2;
    }
    runs = read_draws(in);
  }

  for (auto& [label, draws] : runs) {
    env.draws = draws;
    env.k = 0;
    env.recording = false;
    emit_line("{\"ev\":\"run\",\"label\":" + json_string(label) + "}");
    auto tree = factory.createTree(main_id);
    env.recording = true;
    NodeStatus status = NodeStatus::IDLE;
    try {
      for (int t = 0; t < max_ticks; ++t) {
        status = tree.tickExactlyOnce();
        emit_line(std::string("{\"ev\":\"root\",\"status\":\"") + status_name(status) + "\"}");
        if (status == NodeStatus::SUCCESS || status == NodeStatus::FAILURE) break;
      }
      if (status == NodeStatus::RUNNING) {
        tree.haltTree();
        emit_line("{\"ev\":\"root\",\"status\":\"HALTED\"}");
      }
    } catch (const std::exception& e) {
      emit_line("{\"ev\":\"error\",\"what\":" + json_string(e.what()) + "}");
    }
    env.recording = false;                             // the tree's destructor halts it again
  }
  std::fwrite(env.out.data(), 1, env.out.size(), stdout);
  return 0;
}
