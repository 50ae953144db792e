"""The bearing stack's axial play as a Python function (kind = "python",
models/bearing_stack_python.toml; docs/own-mechanism.md, "A Python function").

    import poise, bearing_stack_python
    result = poise.run("studies/bearing_stack_python.toml", model=bearing_stack_python.model)

`inputs` holds one NumPy array per parameter, a batch of samples, each in the unit its value is
written in the model file (mm here); the function returns an array per declared output in its
unit. Vectorised, it runs at NumPy's speed.
"""


def model(inputs):
    stack = inputs["bearing_a"] + inputs["spacer"] + inputs["bearing_b"]
    gap = inputs["housing"] - stack
    return {"gap": gap, "gap_share": 100.0 * gap / inputs["housing"]}
