"""The radar budget's declared losses (diffsense.sensors.radar.loss_models): the option table, the
parameter table and the documentation follow the declarations."""

from diffsense.scene import Scene, parameter_table
from diffsense.sensors.radar.loss_models import LOSS_MODELS, loss_models_markdown
from diffsense.sensors.radar.structure import OPTIONS
from helpers.paths import REPO


def test_loss_documentation_is_generated_from_the_declarations():
    assert (REPO / "docs" / "models" / "radar_losses.md").read_text() == loss_models_markdown()


def test_every_declared_choice_is_an_option_with_its_parameters():
    for model in LOSS_MODELS:
        assert OPTIONS[model.option] == (model.default, tuple(model.choices))
        for name, choice in model.choices.items():
            table = parameter_table(Scene("radar", [], {model.option: name, "detectability": "exact", "integration": "coherent"}))
            assert all(q.name in table for q in choice.parameters)
            others = {q.name for c in model.choices.values() for q in c.parameters} - {q.name for q in choice.parameters}
            assert not others & set(table)
