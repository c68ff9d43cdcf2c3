#include "codec/requests.hpp"

namespace lmcfg::codec {

namespace {
constexpr RequestSpec answer(std::uint8_t sub, bool writes, bool keyed, std::uint8_t len) {
  return RequestSpec{sub, writes, keyed, len};
}
}  // namespace

std::optional<RequestSpec> request_spec(std::uint8_t main, std::uint8_t sub) {
  switch (static_cast<Main>(main)) {
    case Main::response:  // §6: 01..04, answered with the default response (+ a word)
      if (sub >= 0x01 && sub <= 0x04) return answer(0x00, false, false, 0);
      return std::nullopt;
    case Main::control_word:  // §7
      if (sub == 0x00) return answer(0x00, true, false, 2);
      return std::nullopt;
    case Main::motion_command:  // §8: header, then the command's parameters
      if (sub == 0x00) return answer(0x00, true, false, 2);
      return std::nullopt;
    case Main::parameter:  // §9: answered with the default response
      if (sub >= kParamDefaultLayerFirst && sub <= kParamDefaultLayerLast)
        return answer(0x00, true, false, 0);
      switch (static_cast<ParamOp>(sub)) {
        case ParamOp::read_ram:
        case ParamOp::read_rom:
        case ParamOp::get_min:
        case ParamOp::get_max:
        case ParamOp::get_default:
          return answer(0x00, false, false, 2);
        case ParamOp::write_ram:
        case ParamOp::write_rom:
        case ParamOp::write_ram_rom:
          return answer(0x00, true, false, 6);
      }
      return std::nullopt;
    case Main::param_config: {  // §10: answered with 50h + sub
      const auto a = static_cast<std::uint8_t>(0x50 + sub);
      switch (static_cast<CfgOp>(sub)) {
        case CfgOp::read_rom:
        case CfgOp::address_usage:  // LinRS 3V27 p27
        case CfgOp::get_type:
        case CfgOp::get_min:
        case CfgOp::get_max:
        case CfgOp::get_default:
          return answer(a, false, true, 2);
        case CfgOp::write_rom:
          return answer(a, true, true, 6);
        case CfgOp::start_modified:
        case CfgOp::start_upid_list:
          return answer(a, false, false, 2);
        case CfgOp::next_modified:  // the UPID field is not used (§10.3; a seed erratum)
        case CfgOp::next_upid:
          return answer(a, false, false, 0);
        case CfgOp::default_os:
        case CfgOp::default_mc:
        case CfgOp::default_intf:
        case CfgOp::default_appl:
          return answer(a, true, false, 0);
      }
      return std::nullopt;
    }
    case Main::curve:  // §11: every answer is 40h
      switch (static_cast<CurveOp>(sub)) {
        case CurveOp::save_to_flash:
        case CurveOp::delete_all:
          return answer(0x40, true, false, 0);
        case CurveOp::delete_one:
          return answer(0x40, true, true, 2);
        case CurveOp::add:
        case CurveOp::write_info:
        case CurveOp::write_data:
          return answer(0x40, true, true, 6);
        case CurveOp::read_sizes:
        case CurveOp::read_info:
        case CurveOp::read_data:
          return answer(0x40, false, true, 2);
      }
      return std::nullopt;
    case Main::program:  // §13: subs 01/04 answer 60h after completion
      switch (static_cast<ProgramOp>(sub)) {
        case ProgramOp::reset_after_completion:
        case ProgramOp::start_after_completion:
          return answer(0x60, true, false, 0);
        case ProgramOp::reset_immediate:
        case ProgramOp::stop_mc:
        case ProgramOp::start_immediate:
          return answer(0x00, true, false, 0);
      }
      return std::nullopt;
    case Main::error_info: {  // §14: answered with 70h + sub
      const auto a = static_cast<std::uint8_t>(0x70 + sub);
      switch (static_cast<ErrorInfoOp>(sub)) {
        case ErrorInfoOp::actual_text:
        case ErrorInfoOp::counters:
          return answer(a, false, false, 0);
        case ErrorInfoOp::text_of_code:
        case ErrorInfoOp::log_entry:
          return answer(a, false, false, 2);
      }
      return std::nullopt;
    }
    case Main::command_table: {  // §12: answered with 80h + sub
      const auto a = static_cast<std::uint8_t>(0x80 + sub);
      switch (static_cast<CtOp>(sub)) {
        case CtOp::save_to_flash:
        case CtOp::delete_all:
          return answer(a, true, false, 0);
        case CtOp::delete_one:
          return answer(a, true, true, 2);
        case CtOp::setup_write:
        case CtOp::write_data:
          return answer(a, true, true, 6);
        case CtOp::setup_read:
        case CtOp::read_data:
        case CtOp::defined_list:
          return answer(a, false, true, 2);
      }
      return std::nullopt;
    }
  }
  return std::nullopt;
}

bool known_main(std::uint8_t main) {
  return main <= static_cast<std::uint8_t>(Main::command_table);
}

std::uint8_t expected_answer_sub(const Telegram& r) {
  const auto s = request_spec(r.main, r.sub);
  return s ? s->answer_sub : 0x00;
}

bool is_write_request(const Telegram& r) {
  const auto s = request_spec(r.main, r.sub);
  return s && s->writes;
}

std::optional<std::uint16_t> request_key(const Telegram& r) {
  const auto s = request_spec(r.main, r.sub);
  if (!s || !s->keyed || r.data.size() < 2) return std::nullopt;
  return static_cast<std::uint16_t>(r.data[0] | r.data[1] << 8);
}

}  // namespace lmcfg::codec
