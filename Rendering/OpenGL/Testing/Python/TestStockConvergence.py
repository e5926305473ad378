"""VTK's stock GPU ray caster converges to the reference integral as its step shrinks, and so
does first-order pre-integration, faster: the GPU rays, texture coordinates and compositing
match the reference's semantics (docs/cli.md, the "hovr render" contract)."""

from hovr import methods as hm
from hovrtesting import Checker, marschner_lobb_scene

c = Checker()
scene = marschner_lobb_scene((96, 96))
renderer = hm.Renderer()
reference = renderer.render("reference", scene, 1.0).image
steps = [1.0, 0.5, 0.25, 0.125]
errors = {}
for method in ("stock", "preint1"):
    errors[method] = []
    for step in steps:
        values, _ = hm.compare(renderer.render(method, scene, step).image, reference)
        errors[method].append(values["rmse"])
    print(method, " ".join("%g: %.5f" % pair for pair in zip(steps, errors[method])))
    for coarse, fine, step in zip(errors[method], errors[method][1:], steps[1:]):
        # First order in the step at least: halving the step must cut the error clearly.
        c.check(fine < 0.75 * coarse, "%s: error shrinks when the step halves to %g "
                "(%.5f -> %.5f)" % (method, step, coarse, fine))
c.check(errors["stock"][-1] < 0.01, "stock at 1/8 voxel is within RMSE 0.01 of the reference")
c.check(errors["preint1"][-1] < 0.003, "preint1 at 1/8 voxel is within RMSE 0.003")
for index, step in enumerate(steps):
    c.check(errors["preint1"][index] < errors["stock"][index],
            "preint1 beats stock at step %g" % step)
renderer.close()
c.finish()
