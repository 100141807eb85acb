import hsr

for step in hsr.steps(hsr.load("models/cube.obj"), "zbuffer", width=200, height=200):
    print(step.index, step.text)  # 1 triangle 0: ... pixels written, ... rejected by the depth test
