"""catwalk.collide"""
