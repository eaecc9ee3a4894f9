"""``diffsense describe``: a kind whose scenes need a part is still described, and every unknown
name on its command line gets the close names it may have meant."""

import json
import re

import pytest

from diffsense.scene import CHAINS


def _one_error_line(err):
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in err
    return lines[0]


def test_sonar_without_parts_lists_its_parts_and_how_to_name_them(run_cli):
    code, out, err = run_cli("describe", "sonar")
    assert code == 0, err
    assert err == ""
    for part in ("sea_noise", "thermal_noise", "receiver_noise", "surface_reverberation",
                 "bottom_reverberation", "volume_reverberation"):
        assert part in out
    for option in ("mode", "waveform", "swerling"):
        assert option in out
    hint = [line for line in out.splitlines() if "--parts" in line and "diffsense describe sonar" in line]
    assert len(hint) == 1, out
    # the command it shows works: it describes a sonar with that part, parameters and outputs
    example = re.search(r"'(diffsense describe sonar [^']*)'", hint[0]).group(1)
    code, out, err = run_cli(*example.split()[1:])
    assert code == 0, err
    assert "Parameters" in out and "Outputs" in out and "source_level_db" in out


def test_passive_sonar_without_parts_shows_a_passive_example(run_cli):
    code, out, err = run_cli("describe", "sonar", "--option", "mode=passive")
    assert code == 0, err
    example = re.search(r"'(diffsense describe sonar [^']*)'", out).group(1)
    assert "--option mode=passive" in example
    code, out, err = run_cli(*example.split()[1:])
    assert code == 0, err


def test_sonar_without_parts_writes_its_parts_and_options_as_json(run_cli, tmp_path):
    path = tmp_path / "sonar.json"
    code, _, err = run_cli("describe", "sonar", "--json", path)
    assert code == 0, err
    d = json.loads(path.read_text())
    assert set(d["parts"]) == set(CHAINS["sonar"].parts)
    assert d["options"]["mode"]["default"] == "active"
    assert "--parts" in d["needs"] and "parameters" not in d


def test_parts_the_chain_rejects_together_are_still_an_error(run_cli):
    code, _, err = run_cli("describe", "sonar", "--parts", "surface_reverberation", "--option", "mode=passive")
    assert code == 2
    assert "mode='active'" in _one_error_line(err)


@pytest.mark.parametrize("args, fragment, meant", [
    (("radar", "--parts", "rainn"), "unknown part 'rainn'", "'rain'"),
    (("radar", "--parts", "rain,multipth"), "unknown part 'multipth'", "'multipath'"),
    (("radar", "--option", "swerlng=1"), "unknown option 'swerlng'", "'swerling'"),
    (("radar", "--option", "matched_filter=two_tune"), "got 'two_tune'", "'two_tuned'"),
    (("radr",), "unknown sensor kind 'radr'", "'radar'"),
])
def test_unknown_name_gets_a_did_you_mean(run_cli, args, fragment, meant):
    code, out, err = run_cli("describe", *args)
    assert code == 2 and out == ""
    line = _one_error_line(err)
    assert fragment in line
    suggestion = re.search(r"\(did you mean ([^)]*)\?\)", line)
    assert suggestion and meant in suggestion.group(1), line


def test_a_name_like_nothing_gets_no_suggestion_but_the_list(run_cli):
    code, _, err = run_cli("describe", "radar", "--parts", "zzzzzz")
    assert code == 2
    line = _one_error_line(err)
    assert "did you mean" not in line
    assert all(part in line for part in CHAINS["radar"].parts)
