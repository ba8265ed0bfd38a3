"""plies-deck-of-cards' captions say what its figures show at each resolution: the ply counts and
the one mesh of the decks, the meshes of the mesh study (two at coarse, three above). The
runs stand in by their counts and cells; no solver."""

from types import SimpleNamespace

import pytest

from validation.cases import plies_deck_of_cards as deck


@pytest.mark.parametrize(
    "resolution, decks, study",
    [
        ("coarse", "for 2 and 4 plies, 20 cells,", "the meshes of 10 and 20 cells"),
        ("default", "for 2, 4 and 8 plies, 20 cells,", "the meshes of 10, 20 and 40 cells"),
    ],
)
def test_the_captions_name_the_resolution_s_ply_counts_and_meshes(resolution, decks, study):
    data = SimpleNamespace(
        decks=[SimpleNamespace(count=n, cells=deck.MIDDLE) for n in deck.COUNTS[resolution]],
        meshes=[SimpleNamespace(count=2, cells=n) for n in deck.MESHES[resolution]],
    )
    assert f"for {deck._runs(data)}," == decks
    assert f"the meshes of {deck._listed([run.cells for run in data.meshes])} cells" == study
