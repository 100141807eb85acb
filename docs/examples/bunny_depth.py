import hsr

scene = hsr.load("models/bunny.obj")
frame = hsr.render(scene, algorithm="zbuffer", lighting="blinn-phong", width=512, height=512)
drawn = frame.depth[frame.face_id[..., 0] >= 0]
print(f"the bunny is {drawn.min():.3f} to {drawn.max():.3f} away along the view axis")
