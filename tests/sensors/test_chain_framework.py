"""The scene/chain framework: static scenes, parameter completion and validation, ordered
budgets, and part tracing. A two-term test chain with a closed-form SNR is registered here."""

import math

import jax
import jax.numpy as jnp
import pytest

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.scene import CHAINS, complete_parameters, evaluate
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect
from diffsense.sensors.parts import count_equations, scene_part, traced_parts
from diffsense.scene import Scene


@scene_part("rain")
def _rain_two_way_loss_db(range_m, rate_mm_h):
    return 2.0 * 0.01 * rate_mm_h * range_m / 1e3


class _LinkChain(Chain):
    kind = "test_link"
    parts = {"rain": "rain on the path"}
    options = {"swerling": (0, (0, 1, 2, 3, 4))}

    def parameters(self, scene):
        ps = [Param("range_m", "m", "range", lo=0.0, lo_open=True),
              Param("power_dbw", "dB", "power", default=60.0)]
        if scene.has("rain"):
            ps.append(Param("rain_rate_mm_h", "mm/h", "rain rate", default=4.0, lo=0.0, part="rain"))
        return collect(ps)

    def outputs(self, scene):
        return {"snr_db": Output("snr_db", "dB", "signal-to-noise ratio")}

    def compute(self, scene, p):
        b = BudgetBuilder()
        b.add("power", p["power_dbw"])
        b.add("spreading R^-4", -40.0 * jnp.log10(p["range_m"]))
        if scene.has("rain"):
            b.add("rain", -_rain_two_way_loss_db(p["range_m"], p["rain_rate_mm_h"]))
        budget = b.build()
        return Evaluation(budget, {"snr_db": budget.total})


@pytest.fixture(autouse=True)
def _registered():
    from diffsense.scene import chain_for

    chain_for(Scene("radar"))  # load the real chains first
    CHAINS["test_link"] = _LinkChain()
    yield
    del CHAINS["test_link"]


def test_budget_total_is_the_closed_form_and_keeps_order():
    ev = evaluate(Scene("test_link", ["rain"]), range_m=1e3)
    assert ev.budget.names == ("power", "spreading R^-4", "rain")
    assert float(ev["snr_db"]) == pytest.approx(60.0 - 120.0 - 0.08, abs=1e-12)


def test_scene_is_hashable_static_and_order_free():
    a = Scene("test_link", ["rain"], {"swerling": 1})
    b = Scene("test_link", ("rain",), [("swerling", 1)])
    assert a == b and hash(a) == hash(b)
    assert a.option("swerling") == 1 and a.option("missing", 7) == 7
    assert a.without_parts("rain").parts == frozenset()


def test_absent_part_is_not_traced_and_costs_nothing():
    clear, rain = Scene("test_link"), Scene("test_link", ["rain"])
    jx = {s: jax.make_jaxpr(lambda p, s=s: evaluate(s, p)["snr_db"])(complete_parameters(s, {"range_m": 1e3}))
          for s in (clear, rain)}
    assert traced_parts(jx[clear]) == set()
    assert traced_parts(jx[rain]) == {"rain"}
    assert count_equations(jx[clear]) < count_equations(jx[rain])


def test_evaluation_is_jit_vmap_grad_able():
    s = Scene("test_link", ["rain"])
    f = jax.jit(lambda r: evaluate(s, range_m=r)["snr_db"])
    r = jnp.array([1e3, 2e3])
    assert jnp.allclose(jax.vmap(f)(r), 60.0 - 40.0 * jnp.log10(r) - 0.02 * 4.0 * r / 1e3, rtol=1e-14)
    g = jax.grad(f)(1e3)
    assert float(g) == pytest.approx(-40.0 / (1e3 * math.log(10.0)) - 0.02 * 4.0 / 1e3, rel=1e-13)


@pytest.mark.parametrize("scene,params,message", [
    (Scene("test_link", ["fog"]), {"range_m": 1.0}, "unknown part"),
    (Scene("test_link", (), {"detector": "x"}), {"range_m": 1.0}, "unknown option"),
    (Scene("test_link", (), {"swerling": 7}), {"range_m": 1.0}, "must be one of"),
    (Scene("test_link"), {"range_m": -1.0}, "range_m"),
    (Scene("test_link"), {"rng": 1.0, "range_m": 1.0}, "unknown parameter"),
    (Scene("test_link"), {}, "missing required"),
    (Scene("test_link"), {"range_m": 1.0, "rain_rate_mm_h": 2.0}, "unknown parameter"),
    (Scene("no_such_sensor"), {}, "unknown sensor kind"),
])
def test_bad_scene_or_parameters_raise_domain_error(scene, params, message):
    with pytest.raises(DomainError, match=message):
        evaluate(scene, params)
