"""catwalk.render"""
