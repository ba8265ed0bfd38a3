"""A series' frames have one name whichever solver wrote them: ``<stem>_00000.vtu``, ... (five
digits), as the README names them and as an explicit run streams them (solvers/output.py):
relaxation wrote result_0000.vtu where static and explicit wrote result_00000.vtu."""

from elements import Cable
from femcore import Mesh, Model
from solvers.common import empty_result, make_frame


def test_result_write_names_its_frames_with_five_digits(tmp_path):
    model = Model(Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 2))
    model.add(Cable(axial_stiffness=1e3, mass_per_length=1e-9))
    compiled = model.compile()
    state = compiled.initial_state()
    frames = [make_frame(compiled, state), make_frame(compiled, state)]
    frames[1].time = 1.0
    empty_result(compiled, frames).write(tmp_path / "result.pvd")
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "result.pvd",
        "result_00000.vtu",
        "result_00001.vtu",
    ]
    assert 'file="result_00001.vtu"' in (tmp_path / "result.pvd").read_text()
