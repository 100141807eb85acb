import hsr

scene = hsr.load("models/bunny.obj")
frame = hsr.render(scene, algorithm="zbuffer", lighting="blinn-phong", width=512, height=512)
frame.color      # (512, 512, 3) uint8, a read-only view of hsr's own buffer
frame.depth      # (512, 512) float32: distance along the view axis, +inf where nothing is drawn
frame.face_id    # (512, 512, 3) int32: object, face, instance; -1 where nothing is drawn
frame.save("bunny.png")
